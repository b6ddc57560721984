// polycut-igtl's loop (see igtl_bridge.hpp).
#include "igtl_bridge.hpp"

#include "control_client.hpp"
#include "igtl_messages.hpp"
#include "polycut/common/error.hpp"
#include "surface_mirror.hpp"

#include <algorithm>
#include <arpa/inet.h>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <fcntl.h>
#include <map>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zmq_addon.hpp>

namespace polycut::igtl_bridge {

namespace {

using Clock = std::chrono::steady_clock;

/// A listening TCP socket on host:port (IPv4).
int listen_on(const std::string& host, int port) {
    sockaddr_in address {};
    address.sin_family = AF_INET;
    address.sin_port = htons(std::uint16_t(port));
    if (::inet_pton(AF_INET, host == "localhost" ? "127.0.0.1" : host.c_str(), &address.sin_addr)
        != 1) {
        throw InputError("--host", "not an IPv4 address: " + host);
    }
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0
        || ::listen(fd, 8) != 0) {
        if (fd >= 0) {
            ::close(fd);
        }
        throw Error(host + ":" + std::to_string(port), "cannot listen for OpenIGTLink clients");
    }
    return fd;
}

int bound_port(int fd) {
    sockaddr_in address {};
    socklen_t size = sizeof address;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
    return ntohs(address.sin_port);
}

/// An OpenIGTLink client: its socket and the bytes of a message being received.
struct Client {
    int fd = -1;
    std::vector<std::uint8_t> inbox;
};

/// A tool driven by TRANSFORM messages of one device name.
struct Tool {
    bool scalpel = false;
    std::uint64_t stroke = 0; ///< scalpel: stroke id
    std::optional<std::uint64_t> grab; ///< grab: id once the server answered
    std::optional<std::int64_t> grab_request; ///< grab: the request awaiting its id
    std::array<double, 3> target {}; ///< grab: latest anchor [m]
    bool target_pending = false; ///< grab: a pose arrived before the id
    Clock::time_point last_pose;
};

bool is_scalpel(std::string name) {
    for (char& c : name) {
        c = char(std::tolower(static_cast<unsigned char>(c)));
    }
    return name.find("scalpel") != std::string::npos || name.find("blade") != std::string::npos;
}

class Bridge {
public:
    explicit Bridge(const BridgeOptions& options)
        : m_options(options)
        , m_control(m_context, options.control)
        , m_stream(m_context, zmq::socket_type::sub) {
        m_stream.set(zmq::sockopt::linger, 0);
        m_control.socket().set(zmq::sockopt::linger, 0);
    }

    BridgeSummary run(const std::atomic<bool>& stop, void (*on_listening)(int)) {
        m_listen = listen_on(m_options.host, m_options.port);
        on_listening(bound_port(m_listen));
        m_hello = m_control.send(protocol::HelloParams { "polycut-igtl", std::nullopt });
        m_hello_sent = Clock::now();
        while (!stop) {
            poll_once();
            finish_idle_tools();
            publish();
        }
        for (auto& c : m_clients) {
            ::close(c.fd);
        }
        ::close(m_listen);
        m_summary.snapshots = m_mirror.snapshots();
        return m_summary;
    }

private:
    void poll_once() {
        std::vector<zmq::pollitem_t> items { { m_control.socket().handle(), 0, ZMQ_POLLIN, 0 },
            { m_stream.handle(), 0, ZMQ_POLLIN, 0 }, { nullptr, m_listen, ZMQ_POLLIN, 0 } };
        for (const auto& c : m_clients) {
            items.push_back({ nullptr, c.fd, ZMQ_POLLIN, 0 });
        }
        try {
            zmq::poll(items.data(), items.size(), std::chrono::milliseconds(10));
        } catch (const zmq::error_t& e) {
            if (e.num() == EINTR) {
                return; // a signal: the caller's stop flag says whether to go on
            }
            throw;
        }
        if (items[0].revents & ZMQ_POLLIN) {
            on_reply();
        }
        while (m_subscribed && (items[1].revents & ZMQ_POLLIN)) {
            on_stream();
            items[1].revents = m_stream.get(zmq::sockopt::events) & ZMQ_POLLIN;
        }
        if (items[2].revents & ZMQ_POLLIN) {
            accept_client();
        }
        for (std::size_t k = 3; k < items.size(); ++k) {
            if (items[k].revents & (ZMQ_POLLIN | ZMQ_POLLERR)) {
                read_client(items[k].fd);
            }
        }
        std::erase_if(m_clients, [](const Client& c) { return c.fd < 0; });
        // The server did not answer (down or restarting): ask again.
        const auto now = Clock::now();
        if (!m_subscribed && m_hello && now - m_hello_sent > std::chrono::seconds(2)) {
            m_hello = m_control.send(protocol::HelloParams { "polycut-igtl", std::nullopt });
            m_hello_sent = now;
        }
        if (m_snapshot && now - m_snapshot_sent > std::chrono::seconds(2)) {
            request_snapshot(true);
        }
    }

    void on_reply() {
        std::optional<protocol::Reply> reply;
        try {
            reply = m_control.receive(std::chrono::milliseconds(0));
        } catch (const Error&) {
            return; // a late reply to a request given up on
        }
        if (!reply) {
            return;
        }
        const auto id = std::get<std::int64_t>(reply->id);
        if (!reply->ok()) {
            log("server: " + record::describe(std::get<protocol::RpcError>(reply->outcome)));
            for (auto& [name, tool] : m_tools) {
                if (tool.grab_request == id) {
                    tool.grab_request.reset();
                }
            }
            return;
        }
        auto& result = std::get<protocol::Result>(reply->outcome);
        if (m_hello == id) {
            m_hello.reset();
            const auto& hello = std::get<protocol::HelloResult>(result);
            m_stream.connect(hello.stream);
            m_stream.set(zmq::sockopt::subscribe, std::string(protocol::kSurfaceTopic));
            m_subscribed = true;
            request_snapshot(false);
            log("connected to " + m_options.control + ", stream " + hello.stream);
        } else if (m_snapshot == id) {
            m_snapshot.reset();
            if (m_mirror.snapshot(std::move(std::get<protocol::SurfaceSnapshot>(result)))
                == SurfaceMirror::Next::NeedSnapshot) {
                request_snapshot(false);
            }
            m_changed = true;
        } else {
            for (auto& [name, tool] : m_tools) {
                if (tool.grab_request == id) {
                    tool.grab_request.reset();
                    tool.grab = std::get<protocol::Created>(result).id;
                    if (tool.target_pending) {
                        m_control.send(protocol::MoveGrabParams { *tool.grab, tool.target });
                        tool.target_pending = false;
                    }
                }
            }
        }
    }

    void request_snapshot(bool retry) {
        if (m_snapshot && !retry) {
            return;
        }
        m_snapshot = m_control.send(protocol::GetSurfaceParams {});
        m_snapshot_sent = Clock::now();
    }

    void on_stream() {
        std::vector<zmq::message_t> parts;
        (void)zmq::recv_multipart(m_stream, std::back_inserter(parts));
        std::vector<std::string_view> frames;
        for (const auto& p : parts) {
            frames.emplace_back(static_cast<const char*>(p.data()), p.size());
        }
        auto decoded = protocol::decode_stream(frames);
        if (!decoded) {
            return;
        }
        if (auto* frame = std::get_if<protocol::SurfaceFrame>(&decoded.value())) {
            switch (m_mirror.frame(std::move(*frame))) {
            case SurfaceMirror::Next::Updated:
                m_changed = true;
                break;
            case SurfaceMirror::Next::NeedSnapshot:
                request_snapshot(false);
                break;
            case SurfaceMirror::Next::Nothing:
                break;
            }
        }
    }

    void accept_client() {
        const int fd = ::accept4(m_listen, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) {
            return;
        }
        m_clients.push_back({ fd, {} });
        ++m_summary.clients;
        log("OpenIGTLink client connected");
        if (m_mirror.surface()) {
            send(m_clients.back(),
                pack_polydata(*m_mirror.surface(), m_options.device, m_options.mm_per_m));
        }
    }

    void read_client(int fd) {
        auto it = std::find_if(
            m_clients.begin(), m_clients.end(), [fd](const Client& c) { return c.fd == fd; });
        std::uint8_t buffer[65536];
        const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
        if (n <= 0) {
            ::close(fd);
            it->fd = -1;
            log("OpenIGTLink client disconnected");
            return;
        }
        auto& inbox = it->inbox;
        inbox.insert(inbox.end(), buffer, buffer + n);
        while (inbox.size() >= header_size()) {
            const auto header = unpack_header(inbox.data(), inbox.size());
            if (!header || header->body_size > (64u << 20)) {
                ::close(fd); // not OpenIGTLink
                it->fd = -1;
                return;
            }
            const std::size_t total = header_size() + header->body_size;
            if (inbox.size() < total) {
                return;
            }
            std::vector<std::uint8_t> message(inbox.begin(), inbox.begin() + long(total));
            inbox.erase(inbox.begin(), inbox.begin() + long(total));
            if (header->type == "TRANSFORM") {
                if (const auto pose = unpack_transform(message, m_options.mm_per_m)) {
                    on_pose(*pose);
                }
            }
        }
    }

    void on_pose(const ToolPose& pose) {
        ++m_summary.transforms;
        const auto now = Clock::now();
        auto [it, fresh] = m_tools.try_emplace(pose.device);
        Tool& tool = it->second;
        tool.last_pose = now;
        if (fresh) {
            tool.scalpel = is_scalpel(pose.device);
            tool.stroke = m_next_stroke++;
        }
        if (tool.scalpel) {
            protocol::ScalpelParams sample;
            sample.stroke = tool.stroke;
            sample.a = pose.origin;
            for (int k = 0; k < 3; ++k) {
                sample.b[k] = pose.origin[k] + m_options.blade_length * pose.axis[k];
            }
            m_control.send(sample);
            return;
        }
        tool.target = pose.origin;
        if (fresh) {
            protocol::GrabParams grab;
            grab.point = pose.origin;
            grab.stiffness = m_options.grab_stiffness;
            tool.grab_request = m_control.send(grab);
        } else if (tool.grab) {
            m_control.send(protocol::MoveGrabParams { *tool.grab, tool.target });
        } else {
            tool.target_pending = true;
        }
    }

    void finish_idle_tools() {
        const auto now = Clock::now();
        for (auto it = m_tools.begin(); it != m_tools.end();) {
            const Tool& tool = it->second;
            if (now - tool.last_pose < std::chrono::duration<double>(m_options.idle_s)
                || tool.grab_request) {
                ++it;
                continue;
            }
            if (tool.scalpel) {
                m_control.send(protocol::EndStrokeParams { tool.stroke });
            } else if (tool.grab) {
                m_control.send(protocol::ReleaseParams { *tool.grab });
            }
            it = m_tools.erase(it);
        }
    }

    void publish() {
        const auto now = Clock::now();
        if (!m_changed || !m_mirror.surface() || m_clients.empty()
            || now - m_last_publish < std::chrono::duration<double>(1.0 / m_options.rate_hz)) {
            return;
        }
        m_changed = false;
        m_last_publish = now;
        const Packed message
            = pack_polydata(*m_mirror.surface(), m_options.device, m_options.mm_per_m);
        for (auto& c : m_clients) {
            send(c, message);
        }
        std::erase_if(m_clients, [](const Client& c) { return c.fd < 0; });
    }

    void send(Client& client, const Packed& message) {
        std::size_t at = 0;
        while (at < message.size()) {
            const ssize_t n
                = ::send(client.fd, message.data() + at, message.size() - at, MSG_NOSIGNAL);
            if (n <= 0) {
                ::close(client.fd);
                client.fd = -1;
                return;
            }
            at += std::size_t(n);
        }
        ++m_summary.polydata_sent;
    }

    void log(const std::string& text) const {
        if (!m_options.quiet) {
            std::fprintf(stderr, "polycut-igtl: %s\n", text.c_str());
        }
    }

    const BridgeOptions& m_options;
    zmq::context_t m_context { 1 };
    record::ControlClient m_control;
    zmq::socket_t m_stream;
    bool m_subscribed = false;
    std::optional<std::int64_t> m_hello, m_snapshot;
    Clock::time_point m_hello_sent, m_snapshot_sent, m_last_publish;
    SurfaceMirror m_mirror;
    bool m_changed = false;
    int m_listen = -1;
    std::vector<Client> m_clients;
    std::map<std::string, Tool> m_tools;
    std::uint64_t m_next_stroke = 1;
    BridgeSummary m_summary;
};

} // namespace

BridgeSummary run_bridge(
    const BridgeOptions& options, const std::atomic<bool>& stop, void (*on_listening)(int)) {
    Bridge bridge(options);
    return bridge.run(stop, on_listening);
}

} // namespace polycut::igtl_bridge
