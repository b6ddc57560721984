// polycut-web's bridge without a browser: the frame envelope, the loopback rule, the HTTP side
// (app files, no path escapes, the scene list, the same-origin rule for WebSockets) and the
// WebSocket <-> ZeroMQ relay against a fake server (ROUTER + PUB) whose frames must arrive
// byte for byte.
#include "beast.hpp"
#include "envelope.hpp"
#include "web_server.hpp"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <thread>
#include <zmq.hpp>
#include <zmq_addon.hpp>

namespace polycut::web {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using json = nlohmann::json;

TEST(Envelope, RoundTripsFramesByteForByte) {
    const std::vector<std::string> frames
        = { "surface", R"({"seq": 1})", std::string("\0\x01\xff\x7f", 4), "" };
    const std::string packed = pack_frames(frames);
    EXPECT_EQ(packed.size(), 4 + 4 * frames.size() + 7 + 10 + 4 + 0);
    const auto back = unpack_frames(packed, 8);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, frames);
}

TEST(Envelope, RejectsMalformedEnvelopes) {
    const std::string good = pack_frames({ "abc", "de" });
    EXPECT_FALSE(unpack_frames(good.substr(0, good.size() - 1), 8)); // truncated
    EXPECT_FALSE(unpack_frames(good + "x", 8)); // trailing bytes
    EXPECT_FALSE(unpack_frames(good, 1)); // too many frames
    EXPECT_FALSE(unpack_frames(std::string(4, '\0'), 8)); // no frame
    EXPECT_FALSE(unpack_frames("ab", 8));
    std::string huge = good;
    huge[4] = '\xff'; // first size far past the end
    EXPECT_FALSE(unpack_frames(huge, 8));
}

TEST(WebServer, LoopbackRule) {
    EXPECT_TRUE(is_loopback("127.0.0.1"));
    EXPECT_TRUE(is_loopback("127.3.2.1"));
    EXPECT_TRUE(is_loopback("::1"));
    EXPECT_TRUE(is_loopback("localhost"));
    EXPECT_FALSE(is_loopback("0.0.0.0"));
    EXPECT_FALSE(is_loopback("192.168.1.10"));
    EXPECT_FALSE(is_loopback("example.org"));
}

/// A fake polycut-server: answers hello with its PUB endpoint and echoes other requests back as
/// a result holding the request, with one binary frame; publishes what the test asks.
class FakeServer {
public:
    FakeServer()
        : m_router(m_context, zmq::socket_type::router)
        , m_pub(m_context, zmq::socket_type::pub) {
        m_router.bind("tcp://127.0.0.1:*");
        m_pub.bind("tcp://127.0.0.1:*");
        control = m_router.get(zmq::sockopt::last_endpoint);
        stream = m_pub.get(zmq::sockopt::last_endpoint);
        m_thread = std::thread([this] { run(); });
    }
    ~FakeServer() {
        m_stop = true;
        m_thread.join();
    }
    void publish(const std::vector<std::string>& frames) {
        std::lock_guard lock(m_mutex);
        m_to_publish.push_back(frames);
    }
    std::string control, stream;

private:
    void run() {
        while (!m_stop) {
            zmq::pollitem_t item { m_router.handle(), 0, ZMQ_POLLIN, 0 };
            zmq::poll(&item, 1, std::chrono::milliseconds(10));
            if (item.revents & ZMQ_POLLIN) {
                std::vector<zmq::message_t> parts;
                (void)zmq::recv_multipart(m_router, std::back_inserter(parts));
                const json request = json::parse(parts.at(1).to_string());
                json result = request["method"] == "hello"
                    ? json { { "stream", stream }, { "scene", "fake" } }
                    : json { { "echo", request },
                          { "blob",
                              { { "$frame", 1 }, { "dtype", "uint8" }, { "shape", { 3 } } } } };
                const json reply
                    = { { "jsonrpc", "2.0" }, { "id", request["id"] }, { "result", result } };
                std::vector<zmq::message_t> out;
                out.emplace_back(parts.at(0).data(), parts.at(0).size());
                out.emplace_back(reply.dump());
                if (request["method"] != "hello") {
                    out.emplace_back(std::string("\x00\x01\x02", 3));
                }
                (void)zmq::send_multipart(m_router, out);
            }
            std::lock_guard lock(m_mutex);
            for (const auto& frames : m_to_publish) {
                std::vector<zmq::message_t> out;
                for (const auto& f : frames) {
                    out.emplace_back(f.data(), f.size());
                }
                (void)zmq::send_multipart(m_pub, out);
            }
            m_to_publish.clear();
        }
    }
    zmq::context_t m_context;
    zmq::socket_t m_router, m_pub;
    std::atomic<bool> m_stop { false };
    std::mutex m_mutex;
    std::vector<std::vector<std::string>> m_to_publish;
    std::thread m_thread;
};

/// polycut-web in this process, on a free port, with an app and a scene directory of its own.
class Bridge : public ::testing::Test {
protected:
    void SetUp() override {
        root = std::filesystem::temp_directory_path()
            / ("polycut-web-test-" + std::to_string(::getpid()) + "-"
                + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(root / "app");
        std::filesystem::create_directories(root / "scenes");
        std::ofstream(root / "app" / "index.html") << "<html>polycut</html>";
        std::ofstream(root / "secret.txt") << "not served";
        for (const char* name : { "b_scene.json", "a_scene.json", "bad name.json", "x.txt" }) {
            std::ofstream(root / "scenes" / name) << "{}";
        }
        WebOptions options;
        options.control = fake.control;
        options.port = 0;
        options.app_dir = (root / "app").string();
        options.scene_dir = (root / "scenes").string();
        server = std::make_unique<WebServer>(options);
        thread = std::thread([this] { server->run(); });
    }
    void TearDown() override {
        server->stop();
        thread.join();
        server.reset();
        std::filesystem::remove_all(root);
    }

    http::response<http::string_body> get(const std::string& target) {
        net::io_context io;
        beast::tcp_stream stream(io);
        stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), server->port()));
        http::request<http::empty_body> req { http::verb::get, target, 11 };
        req.set(http::field::host, "127.0.0.1");
        http::write(stream, req);
        beast::flat_buffer buffer;
        http::response<http::string_body> res;
        http::read(stream, buffer, res);
        return res;
    }

    FakeServer fake;
    std::filesystem::path root;
    std::unique_ptr<WebServer> server;
    std::thread thread;
};

TEST_F(Bridge, ServesTheAppAndTheSceneListAndNothingElse) {
    const auto index = get("/");
    EXPECT_EQ(index.result(), http::status::ok);
    EXPECT_EQ(index.body(), "<html>polycut</html>");
    EXPECT_EQ(std::string(index[http::field::content_type]), "text/html; charset=utf-8");
    EXPECT_EQ(get("/../secret.txt").result(), http::status::not_found);
    EXPECT_EQ(get("/%2e%2e/secret.txt").result(), http::status::not_found);
    EXPECT_EQ(get("/missing.js").result(), http::status::not_found);
    const json scenes = json::parse(get("/api/scenes").body());
    EXPECT_EQ(scenes["scenes"], json({ "a_scene", "b_scene" })); // sorted; bad names left out
}

TEST_F(Bridge, RelaysRequestsRepliesAndStreamFramesUnchanged) {
    net::io_context io;
    websocket::stream<tcp::socket> ws(io);
    ws.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), server->port()));
    ws.handshake("127.0.0.1", "/ws");
    beast::flat_buffer buffer;
    ws.read(buffer);
    ASSERT_TRUE(ws.got_text());
    const json ready = json::parse(beast::buffers_to_string(buffer.data()));
    EXPECT_EQ(ready["bridge"], "ready");
    EXPECT_EQ(ready["stream"], fake.stream);

    // A request as text; the reply comes back as an envelope holding the server's frames.
    const json request = { { "jsonrpc", "2.0" }, { "id", 7 }, { "method", "get_stats" } };
    ws.text(true);
    ws.write(net::buffer(request.dump()));
    buffer.consume(buffer.size());
    ws.read(buffer);
    ASSERT_TRUE(ws.got_binary());
    const auto reply = unpack_frames(beast::buffers_to_string(buffer.data()), 8);
    ASSERT_TRUE(reply);
    ASSERT_EQ(reply->size(), 2u);
    EXPECT_EQ(json::parse(reply->at(0))["result"]["echo"], request);
    EXPECT_EQ(reply->at(1), std::string("\x00\x01\x02", 3));

    // A request with a binary frame, as an envelope.
    ws.binary(true);
    const json with_frame = { { "jsonrpc", "2.0" }, { "id", 8 }, { "method", "cut" } };
    ws.write(net::buffer(pack_frames({ with_frame.dump(), std::string(36, '\x01') })));
    buffer.consume(buffer.size());
    ws.read(buffer);
    EXPECT_EQ(
        json::parse(unpack_frames(beast::buffers_to_string(buffer.data()), 8)->at(0))["id"], 8);

    // Stream messages: published every 20 ms until one arrives (the subscription takes a
    // moment, and a message published before it is lost: a single publish before a blocking
    // read could wait forever). After 5 s without one the socket is shut down, so the read
    // fails instead of hanging.
    const std::vector<std::string> surface
        = { "surface", R"({"seq": 5})", std::string("\x10\x20\x30\x40", 4) };
    std::atomic<bool> received { false };
    std::thread publisher([&] {
        for (int attempt = 0; attempt < 250 && !received; ++attempt) {
            fake.publish(surface);
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        if (!received) {
            beast::error_code ignored;
            ws.next_layer().shutdown(tcp::socket::shutdown_both, ignored);
        }
    });
    buffer.consume(buffer.size());
    beast::error_code ec;
    ws.read(buffer, ec);
    received = true;
    publisher.join();
    ASSERT_FALSE(ec) << "no stream message within 5 s: " << ec.message();
    const std::optional<std::vector<std::string>> got
        = unpack_frames(beast::buffers_to_string(buffer.data()), 8);
    ASSERT_TRUE(got);
    EXPECT_EQ(*got, surface);
    ws.close(websocket::close_code::normal);
}

TEST_F(Bridge, RefusesWebSocketsFromOtherSitesPages) {
    net::io_context io;
    websocket::stream<tcp::socket> ws(io);
    ws.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), server->port()));
    ws.set_option(websocket::stream_base::decorator(
        [](websocket::request_type& req) { req.set(http::field::origin, "http://evil.example"); }));
    beast::error_code ec;
    ws.handshake("127.0.0.1:" + std::to_string(server->port()), "/ws", ec);
    EXPECT_TRUE(ec) << "the handshake from another origin was accepted";
}

} // namespace
} // namespace polycut::web
