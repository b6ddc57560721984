// polycut::server::Server: the real-time server (issue 6 item 4, DESIGN.md sec. 5). A ROUTER
// control socket speaking JSON-RPC 2.0 (docs/protocol.md) and a PUB stream socket, driven by one
// thread: a fixed-rate loop on an absolute steady_clock schedule that, while it waits for the
// next deadline, polls the control socket and applies commands at tick boundaries in arrival
// order, then steps the simulation and publishes the surface. ZeroMQ stays in the .cpp files.
#pragma once

#include "polycut/protocol/limits.hpp"
#include "server_reply_cache.hpp"
#include "server_strokes.hpp"

#include <atomic>
#include <memory>
#include <optional>
#include <string>

namespace polycut::server {

/// Server settings (the command line of polycut-server).
struct ServerConfig {
    /// Scene loaded at start (any path; only the command line may name a path). None: the
    /// server starts without a scene and waits for load_scene.
    std::optional<std::string> scene_file;
    /// Scene directory for load_scene {"name"}; empty: the scene file's directory, else
    /// "assets/scenes".
    std::string scene_dir;
    /// Control (ROUTER) endpoint; "tcp://127.0.0.1:*" binds an ephemeral port.
    std::string control = "tcp://127.0.0.1:5555";
    /// Stream (PUB) endpoint.
    std::string stream = "tcp://127.0.0.1:5556";
    double rate_hz = 60.0; ///< tick rate [Hz], in (0, limits.max_rate_hz]
    bool paused = false; ///< start paused (ticks only on step/resume)
    /// Append every applied command to this file as JSON lines (server_command_log.hpp).
    std::optional<std::string> record_commands;
    protocol::Limits limits; ///< wire limits (hello reports them)
    int stream_hwm = 8; ///< PUB send high-water mark [messages]
    double client_ttl_s = 60.0; ///< a silent client's state (strokes, cached replies) goes [s]
    std::size_t max_clients = 4096; ///< clients with state; the least recently seen goes first
    ReplyCacheLimits reply_cache;
    StrokeLimits strokes;
    bool log_stats = true; ///< one info line per second on stderr
    /// CURVE key directory (server_curve.hpp): both sockets encrypt and only the clients in its
    /// authorized_clients get in. None: plain TCP, allowed only on loopback endpoints.
    std::optional<std::string> curve_keys;
    /// Allow a non-loopback endpoint without CURVE (anyone who can reach it may drive the server).
    bool insecure = false;
};

/// The server. Construct (loads the scene, binds both sockets; throws polycut::Error or
/// std::runtime_error on failure), read the bound endpoints, then run() on one thread.
class Server {
public:
    explicit Server(ServerConfig config);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    /// The bound control endpoint, with the actual port (e.g. "tcp://127.0.0.1:40123").
    std::string control_endpoint() const;
    /// The bound stream endpoint.
    std::string stream_endpoint() const;

    /// Runs the loop until `shutdown` or request_stop(); writes the command log's end marker.
    void run();
    /// True while a `load_scene` is being built on its worker thread. The build cannot be
    /// interrupted and the destructor waits for it; a process that wants to stop at once (on a
    /// signal) exits without destroying the server instead.
    bool scene_build_in_flight() const;
    /// Asks run() to return at the next poll (at most ~100 ms later). Thread-safe and
    /// async-signal-safe.
    void request_stop() noexcept { m_stop.store(true, std::memory_order_relaxed); }

    struct Impl;

private:
    std::atomic<bool> m_stop { false };
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::server
