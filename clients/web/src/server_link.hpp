// One browser's link to polycut-server: a DEALER on the control endpoint carries the browser's
// JSON-RPC requests and their replies unchanged, and a SUB on the stream carries the surface
// frames and events unchanged. The link finds the stream endpoint with its own `hello` and
// subscribes before it reports "ready", so the browser can follow the Clone pattern of
// docs/protocol.md (subscribe, then get_surface). ZeroMQ reconnects both sockets by itself when
// the server restarts on the same endpoints. The sockets live on the link's own thread.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

namespace polycut::web {

/// Settings of a link.
struct LinkOptions {
    std::string control = "tcp://127.0.0.1:5555"; ///< the server's control endpoint
    /// How long the link's own hello waits for the server before it tries again [ms].
    std::chrono::milliseconds hello_timeout { 1000 };
};

/// A ZeroMQ message, frame by frame.
using Frames = std::vector<std::string>;

class ServerLink {
public:
    /// Called on the link's thread with every message from the server: a reply (`stream`
    /// false) or a stream message (`stream` true, frame 0 the topic).
    using Deliver = std::function<void(Frames frames, bool stream)>;
    /// Called on the link's thread with a status as JSON text: {"bridge": "ready", "stream":
    /// ENDPOINT, "scene": NAME} once subscribed, {"bridge": "waiting", "control": ENDPOINT} while
    /// the server does not answer.
    using Status = std::function<void(std::string json)>;

    /// Starts the link's thread: it connects the DEALER at once and subscribes once its hello
    /// is answered.
    ServerLink(zmq::context_t& context, LinkOptions options, Deliver deliver, Status status);
    /// Stops the thread and closes the sockets.
    ~ServerLink();
    ServerLink(const ServerLink&) = delete;
    ServerLink& operator=(const ServerLink&) = delete;

    /// Queues a request for the server (any thread).
    void send(Frames frames);

private:
    void run();

    zmq::context_t& m_context;
    LinkOptions m_options;
    Deliver m_deliver;
    Status m_status;
    std::string m_inbox_endpoint;
    std::mutex m_input_mutex;
    zmq::socket_t m_input; ///< PAIR to the thread's inbox, used under m_input_mutex
    std::atomic<bool> m_stop { false };
    std::thread m_thread;
};

} // namespace polycut::web
