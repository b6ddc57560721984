// polycut-web's HTTP and WebSocket server (see web_server.hpp), after Boost.Beast's
// advanced_server example: an acceptor, one HttpSession per TCP connection, which becomes a
// WsSession on an upgrade of /ws.
#include "web_server.hpp"

#include "beast.hpp"
#include "envelope.hpp"
#include "polycut/common/error.hpp"
#include "server_link.hpp"

#include <csignal>
#include <deque>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

namespace polycut::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

/// Frames a browser's request may have: the server's default limits.max_frames_per_message (a
/// larger envelope is refused here; the server applies its own limit to the rest).
constexpr std::size_t kMaxRequestFrames = 8;

std::string mime_type(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".html") {
        return "text/html; charset=utf-8";
    }
    if (ext == ".js") {
        return "text/javascript; charset=utf-8";
    }
    if (ext == ".css") {
        return "text/css; charset=utf-8";
    }
    if (ext == ".json") {
        return "application/json";
    }
    if (ext == ".png") {
        return "image/png";
    }
    return "application/octet-stream";
}

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

/// The scene names of a directory (files NAME.json with NAME as load_scene accepts it), sorted.
std::string scene_list(const std::string& dir) {
    nlohmann::json names = nlohmann::json::array();
    std::error_code ec;
    if (!dir.empty() && std::filesystem::is_directory(dir, ec)) {
        std::vector<std::string> found;
        static const std::regex kName("[A-Za-z0-9_-]{1,64}");
        for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
            const auto p = e.path();
            if (p.extension() == ".json" && std::regex_match(p.stem().string(), kName)) {
                found.push_back(p.stem().string());
            }
        }
        std::sort(found.begin(), found.end());
        names = found;
    }
    return nlohmann::json { { "scenes", names } }.dump();
}

/// One browser's WebSocket, bridged to the server through a ServerLink.
class WsSession : public std::enable_shared_from_this<WsSession> {
public:
    WsSession(tcp::socket socket, const WebOptions& options, zmq::context_t& context)
        : m_ws(std::move(socket))
        , m_options(options)
        , m_context(context) { }

    ~WsSession() {
        // The link's thread may still call deliver(); it only posts to the (gone) session
        // through a weak pointer, so stopping it here is safe.
        m_link.reset();
    }

    void run(http::request<http::string_body> request) {
        m_ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        m_ws.read_message_max(16u << 20);
        m_ws.async_accept(
            request, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
    }

private:
    void on_accept(beast::error_code ec) {
        if (ec) {
            return;
        }
        const std::weak_ptr<WsSession> weak = shared_from_this();
        const auto executor = m_ws.get_executor();
        LinkOptions link;
        link.control = m_options.control;
        m_link = std::make_unique<ServerLink>(
            m_context, link,
            [weak, executor](Frames frames, bool stream) {
                net::post(executor, [weak, stream, message = pack_frames(frames)]() mutable {
                    if (auto self = weak.lock()) {
                        self->queue(std::move(message), true, stream);
                    }
                });
            },
            [weak, executor](std::string status) {
                net::post(executor, [weak, status = std::move(status)]() mutable {
                    if (auto self = weak.lock()) {
                        self->queue(std::move(status), false, false);
                    }
                });
            });
        read();
    }

    void read() {
        m_ws.async_read(
            m_buffer, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
    }

    void on_read(beast::error_code ec, std::size_t) {
        if (ec) {
            m_link.reset(); // closed: stop the ZeroMQ side now
            return;
        }
        const std::string message = beast::buffers_to_string(m_buffer.data());
        m_buffer.consume(m_buffer.size());
        if (m_ws.got_text()) {
            m_link->send({ message });
        } else if (auto frames = unpack_frames(message, kMaxRequestFrames)) {
            m_link->send(std::move(*frames));
        } else {
            // Not an envelope: say so as the server says what is wrong with a message.
            queue(nlohmann::json { { "bridge", "error" },
                      { "reason", "a binary message must be a frame envelope (docs/viewer.md)" } }
                      .dump(),
                false, false);
        }
        read();
    }

    /// Queues a message for the browser; a stream message over the queue limit is dropped.
    void queue(std::string message, bool binary, bool stream) {
        if (stream && m_queued_stream >= m_options.max_queued_frames) {
            return;
        }
        m_queued_stream += stream ? 1 : 0;
        m_out.push_back({ std::move(message), binary, stream });
        if (m_out.size() == 1) {
            write();
        }
    }

    void write() {
        m_ws.binary(m_out.front().binary);
        m_ws.async_write(net::buffer(m_out.front().data),
            beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
    }

    void on_write(beast::error_code ec, std::size_t) {
        if (ec) {
            return;
        }
        m_queued_stream -= m_out.front().stream ? 1 : 0;
        m_out.pop_front();
        if (!m_out.empty()) {
            write();
        }
    }

    struct Outgoing {
        std::string data;
        bool binary = true;
        bool stream = false;
    };

    websocket::stream<beast::tcp_stream> m_ws;
    const WebOptions& m_options;
    zmq::context_t& m_context;
    beast::flat_buffer m_buffer;
    std::deque<Outgoing> m_out;
    std::size_t m_queued_stream = 0;
    std::unique_ptr<ServerLink> m_link;
};

/// One HTTP connection: static files, /api/scenes, and the upgrade of /ws.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket socket, const WebOptions& options, zmq::context_t& context)
        : m_stream(std::move(socket))
        , m_options(options)
        , m_context(context) { }

    void run() { read(); }

private:
    void read() {
        m_request = {};
        m_stream.expires_after(std::chrono::seconds(30));
        http::async_read(m_stream, m_buffer, m_request,
            beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
    }

    void on_read(beast::error_code ec, std::size_t) {
        if (ec) {
            return;
        }
        const std::string target(m_request.target());
        if (websocket::is_upgrade(m_request)) {
            if (target != "/ws" || !same_origin()) {
                return respond(http::status::forbidden, "text/plain",
                    "WebSocket only at /ws, from a page this server served\n");
            }
            m_stream.expires_never();
            std::make_shared<WsSession>(m_stream.release_socket(), m_options, m_context)
                ->run(std::move(m_request));
            return;
        }
        if (m_request.method() != http::verb::get && m_request.method() != http::verb::head) {
            return respond(http::status::method_not_allowed, "text/plain", "GET only\n");
        }
        std::string path = target.substr(0, target.find('?'));
        if (path == "/api/scenes") {
            return respond(http::status::ok, "application/json", scene_list(m_options.scene_dir));
        }
        if (path == "/") {
            path = "/index.html";
        }
        // Only plain names inside the app directory: no "..", no hidden files.
        static const std::regex kSafe("(/[A-Za-z0-9_][A-Za-z0-9_.-]*)+");
        const std::filesystem::path file
            = std::filesystem::path(m_options.app_dir) / path.substr(1);
        std::error_code fs_ec;
        if (!std::regex_match(path, kSafe) || path.find("..") != std::string::npos
            || !std::filesystem::is_regular_file(file, fs_ec)) {
            return respond(http::status::not_found, "text/plain", "not found: " + path + "\n");
        }
        respond(http::status::ok, mime_type(path), read_file(file));
    }

    /// A browser sends Origin with a WebSocket handshake: it must be this server's own page, so
    /// a page of another site cannot drive the simulator through the user's browser.
    bool same_origin() const {
        const auto origin = m_request.find(http::field::origin);
        if (origin == m_request.end()) {
            return true; // not a browser (a script or a test client)
        }
        const auto host = m_request.find(http::field::host);
        return host != m_request.end()
            && std::string(origin->value()) == "http://" + std::string(host->value());
    }

    void respond(http::status status, const std::string& type, std::string body) {
        auto res = std::make_shared<http::response<http::string_body>>(status, m_request.version());
        res->set(http::field::server, "polycut-web");
        res->set(http::field::content_type, type);
        res->set(http::field::cache_control, "no-store");
        res->keep_alive(m_request.keep_alive());
        if (m_request.method() != http::verb::head) {
            res->body() = std::move(body);
        }
        res->prepare_payload();
        http::async_write(
            m_stream, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
                if (ec || !res->keep_alive()) {
                    beast::error_code ignored;
                    self->m_stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
                    return;
                }
                self->read();
            });
    }

    beast::tcp_stream m_stream;
    const WebOptions& m_options;
    zmq::context_t& m_context;
    beast::flat_buffer m_buffer;
    http::request<http::string_body> m_request;
};

} // namespace

bool is_loopback(const std::string& host) {
    if (host == "localhost") {
        return true;
    }
    beast::error_code ec;
    const auto address = net::ip::make_address(host, ec);
    return !ec && address.is_loopback();
}

struct WebServer::Impl {
    WebOptions options;
    zmq::context_t context { 1 };
    net::io_context io { 1 };
    tcp::acceptor acceptor { io };

    void accept() {
        acceptor.async_accept(net::make_strand(io), [this](beast::error_code ec, tcp::socket s) {
            if (!ec) {
                // Small messages (a request, a reply) must not wait for Nagle's algorithm and
                // the peer's delayed ACK: without this a round trip took 40 ms more.
                beast::error_code ignored;
                s.set_option(tcp::no_delay(true), ignored);
                std::make_shared<HttpSession>(std::move(s), options, context)->run();
            }
            if (acceptor.is_open()) {
                accept();
            }
        });
    }
};

WebServer::WebServer(WebOptions options)
    : m_impl(std::make_unique<Impl>()) {
    m_impl->options = std::move(options);
    const std::string where = m_impl->options.host + ":" + std::to_string(m_impl->options.port);
    beast::error_code ec;
    const auto address = net::ip::make_address(
        m_impl->options.host == "localhost" ? "127.0.0.1" : m_impl->options.host, ec);
    if (ec) {
        throw InputError("--http", "not an IP address: " + m_impl->options.host);
    }
    const tcp::endpoint endpoint(address, m_impl->options.port);
    auto& acceptor = m_impl->acceptor;
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) {
        acceptor.set_option(net::socket_base::reuse_address(true), ec);
        acceptor.bind(endpoint, ec);
    }
    if (!ec) {
        acceptor.listen(net::socket_base::max_listen_connections, ec);
    }
    if (ec) {
        throw Error("--http " + where, "cannot listen: " + ec.message());
    }
    m_impl->accept();
}

WebServer::~WebServer() = default;

std::uint16_t WebServer::port() const {
    return m_impl->acceptor.local_endpoint().port();
}

void WebServer::run() {
    net::signal_set signals(m_impl->io, SIGINT, SIGTERM);
    signals.async_wait([this](beast::error_code, int) { stop(); });
    m_impl->io.run();
}

void WebServer::stop() {
    m_impl->io.stop();
}

} // namespace polycut::web
