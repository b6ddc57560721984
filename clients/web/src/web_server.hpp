// polycut-web's HTTP side (Boost.Beast): serves the bundled web app from a directory, the list of
// scene names at /api/scenes, and upgrades /ws to a WebSocket that bridges one browser to
// polycut-server through a ServerLink (docs/viewer.md). One I/O thread; each WebSocket's
// ZeroMQ sockets run on their link's thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace polycut::web {

/// Settings of the web server.
struct WebOptions {
    std::string control = "tcp://127.0.0.1:5555"; ///< polycut-server's control endpoint
    std::string host = "127.0.0.1"; ///< address to listen on (loopback by default)
    std::uint16_t port = 8080; ///< 0 = any free port (the bound port is reported)
    std::string app_dir; ///< the bundled web app (index.html, bundle.js, ...)
    std::string scene_dir; ///< where /api/scenes lists *.json scene names ("" = none)
    /// Stream messages queued for one browser beyond which new ones are dropped (the browser
    /// sees the gap in `seq` and fetches a snapshot, as any client of the stream).
    std::size_t max_queued_frames = 4;
};

class WebServer {
public:
    /// Binds (throws polycut::Error naming the address when it cannot).
    explicit WebServer(WebOptions options);
    ~WebServer();
    WebServer(const WebServer&) = delete;
    WebServer& operator=(const WebServer&) = delete;

    /// The bound port.
    std::uint16_t port() const;
    /// Serves until stop() (from another thread) or SIGINT / SIGTERM.
    void run();
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// True for 127.0.0.0/8, ::1 and "localhost".
bool is_loopback(const std::string& host);

} // namespace polycut::web
