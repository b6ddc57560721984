// The ZeroMQ side of polycut-web (see server_link.hpp).
#include "server_link.hpp"

#include <nlohmann/json.hpp>
#include <zmq_addon.hpp>

namespace polycut::web {

namespace {

std::atomic<long> g_links { 0 };

Frames receive_all(zmq::socket_t& socket) {
    std::vector<zmq::message_t> parts;
    (void)zmq::recv_multipart(socket, std::back_inserter(parts));
    Frames frames;
    frames.reserve(parts.size());
    for (auto& p : parts) {
        frames.emplace_back(p.to_string());
    }
    return frames;
}

void send_all(zmq::socket_t& socket, const Frames& frames) {
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const auto flags = i + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none;
        (void)socket.send(zmq::buffer(frames[i]), flags | zmq::send_flags::dontwait);
    }
}

/// Asks the server for its stream endpoint and scene; nullopt when it does not answer in time.
std::optional<nlohmann::json> hello(
    zmq::context_t& context, const std::string& control, std::chrono::milliseconds timeout) {
    zmq::socket_t probe(context, zmq::socket_type::dealer);
    probe.set(zmq::sockopt::linger, 0);
    probe.connect(control);
    const nlohmann::json request = { { "jsonrpc", "2.0" }, { "id", "polycut-web-hello" },
        { "method", "hello" }, { "params", { { "client", "polycut-web" } } } };
    send_all(probe, { request.dump() });
    zmq::pollitem_t item { probe.handle(), 0, ZMQ_POLLIN, 0 };
    if (zmq::poll(&item, 1, timeout) == 0) {
        return std::nullopt;
    }
    const Frames reply = receive_all(probe);
    const auto j = nlohmann::json::parse(reply.at(0), nullptr, false);
    if (j.is_discarded() || !j.contains("result")) {
        return std::nullopt;
    }
    return j["result"];
}

} // namespace

ServerLink::ServerLink(zmq::context_t& context, LinkOptions options, Deliver deliver, Status status)
    : m_context(context)
    , m_options(std::move(options))
    , m_deliver(std::move(deliver))
    , m_status(std::move(status))
    , m_inbox_endpoint("inproc://polycut-web-link-" + std::to_string(++g_links))
    , m_input(context, zmq::socket_type::pair) {
    m_input.set(zmq::sockopt::linger, 0);
    // The inbox is bound on the link's thread; inproc connect before bind is fine (ZeroMQ >= 4).
    m_input.connect(m_inbox_endpoint);
    m_thread = std::thread([this] { run(); });
}

ServerLink::~ServerLink() {
    m_stop = true;
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

void ServerLink::send(Frames frames) {
    std::lock_guard lock(m_input_mutex);
    send_all(m_input, frames);
}

void ServerLink::run() {
    try {
        zmq::socket_t inbox(m_context, zmq::socket_type::pair);
        inbox.set(zmq::sockopt::linger, 0);
        inbox.bind(m_inbox_endpoint);
        zmq::socket_t control(m_context, zmq::socket_type::dealer);
        control.set(zmq::sockopt::linger, 0);
        control.connect(m_options.control);
        zmq::socket_t stream(m_context, zmq::socket_type::sub);
        stream.set(zmq::sockopt::linger, 0);
        bool subscribed = false;
        auto next_hello = std::chrono::steady_clock::now();
        while (!m_stop) {
            if (!subscribed && std::chrono::steady_clock::now() >= next_hello) {
                if (const auto info
                    = hello(m_context, m_options.control, m_options.hello_timeout)) {
                    // Subscribe first; the browser asks for its snapshot after "ready".
                    stream.connect(info->value("stream", std::string()));
                    stream.set(zmq::sockopt::subscribe, "");
                    subscribed = true;
                    m_status(nlohmann::json { { "bridge", "ready" },
                        { "stream", info->value("stream", std::string()) },
                        { "scene", info->value("scene", std::string()) } }
                                 .dump());
                } else {
                    m_status(
                        nlohmann::json { { "bridge", "waiting" }, { "control", m_options.control } }
                            .dump());
                    next_hello = std::chrono::steady_clock::now() + m_options.hello_timeout;
                }
            }
            zmq::pollitem_t items[] = { { inbox.handle(), 0, ZMQ_POLLIN, 0 },
                { control.handle(), 0, ZMQ_POLLIN, 0 }, { stream.handle(), 0, ZMQ_POLLIN, 0 } };
            zmq::poll(items, subscribed ? 3 : 2, std::chrono::milliseconds(100));
            if (items[0].revents & ZMQ_POLLIN) {
                send_all(control, receive_all(inbox));
            }
            if (items[1].revents & ZMQ_POLLIN) {
                m_deliver(receive_all(control), false);
            }
            if (subscribed && (items[2].revents & ZMQ_POLLIN)) {
                m_deliver(receive_all(stream), true);
            }
        }
    } catch (const std::exception& e) {
        m_status(nlohmann::json { { "bridge", "error" }, { "reason", e.what() } }.dump());
    }
}

} // namespace polycut::web
