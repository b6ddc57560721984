// Test fixture for the server tests: a small scene in a temporary scene directory, a Server
// running in-process on its own thread over tcp://127.0.0.1 with ephemeral ports, and a DEALER
// test client speaking the protocol (polycut::protocol's codec).
#pragma once

#include "polycut/protocol/protocol.hpp"
#include "server.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <unistd.h>
#include <zmq.hpp>

namespace polycut::server::testing {

/// A 4 x 4 x 2 cm block of 4 x 4 x 2 Kuhn-split cubes fixed at its base, under gravity, at
/// 60 Hz: a step takes about a millisecond.
inline const char* kSmallScene = R"({
  "name": "small",
  "description": "4 x 4 x 2 cm block fixed at its base (server tests).",
  "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
               "cells": [4, 4, 2], "elements": "tet"},
  "method": "tet",
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000,
               "rayleigh_stiffness": 0.02},
  "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": true},
  "solver": {"type": "pcg", "preconditioner": "jacobi", "tolerance": 1e-8},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}],
  "loads": {"gravity": [0, 0, -9.81]}
})";

/// Two sweep triangles forming a vertical quad in the plane y = y0 from x0 to x1, from above
/// the block (z = 0.03) down to z = z_low: an incision into the small block's top.
inline std::vector<protocol::Triangle3> incision(double y0, double x0, double x1, double z_low) {
    const protocol::Vector3 a0 { x0, y0, 0.03 }, b0 { x0, y0, z_low }, a1 { x1, y0, 0.03 },
        b1 { x1, y0, z_low };
    return { protocol::Triangle3 { a0, b0, a1 }, protocol::Triangle3 { b0, b1, a1 } };
}

/// A temporary scene directory holding small.json.
class SceneDir {
public:
    SceneDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path()
            / ("polycut_server_" + std::string(info->test_suite_name()) + "_" + info->name() + "_"
                + std::to_string(::getpid()));
        std::filesystem::create_directories(m_path);
        std::ofstream(m_path / "small.json") << kSmallScene;
    }
    ~SceneDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    const std::filesystem::path& path() const { return m_path; }
    std::string file(const std::string& name) const { return (m_path / name).string(); }

private:
    std::filesystem::path m_path;
};

/// The default test configuration: ephemeral loopback ports, the small scene, quiet.
inline ServerConfig test_config(const SceneDir& dir, bool paused) {
    ServerConfig c;
    c.scene_file = dir.file("small.json");
    c.scene_dir = dir.path().string();
    c.control = "tcp://127.0.0.1:*";
    c.stream = "tcp://127.0.0.1:*";
    c.rate_hz = 60.0;
    c.paused = paused;
    c.log_stats = false;
    return c;
}

/// A Server running on its own thread; stopped and joined on destruction.
class RunningServer {
public:
    explicit RunningServer(ServerConfig config)
        : m_server(std::make_unique<Server>(std::move(config)))
        , m_thread([this] {
            m_server->run();
            m_done.store(true);
        }) { }
    ~RunningServer() { stop(); }
    void stop() {
        m_server->request_stop();
        if (m_thread.joinable()) {
            m_thread.join();
        }
    }
    /// Waits for run() to return by itself (after `shutdown`); false on timeout.
    bool wait_stopped(std::chrono::milliseconds timeout) {
        const auto end = std::chrono::steady_clock::now() + timeout;
        while (!m_done.load() && std::chrono::steady_clock::now() < end) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return m_done.load();
    }
    std::string control() const { return m_server->control_endpoint(); }
    std::string stream() const { return m_server->stream_endpoint(); }

private:
    std::unique_ptr<Server> m_server;
    std::atomic<bool> m_done { false };
    std::thread m_thread; ///< last: starts once the members above exist
};

/// Receives a whole multipart message (blocking up to `timeout`).
inline std::optional<protocol::Message> recv_message(
    zmq::socket_t& socket, std::chrono::milliseconds timeout) {
    zmq::pollitem_t item { socket.handle(), 0, ZMQ_POLLIN, 0 };
    zmq::poll(&item, 1, timeout);
    if ((item.revents & ZMQ_POLLIN) == 0) {
        return std::nullopt;
    }
    protocol::Message frames;
    bool more = true;
    while (more) {
        zmq::message_t part;
        (void)socket.recv(part, zmq::recv_flags::none);
        frames.emplace_back(part.data<char>(), part.size());
        more = part.more();
    }
    return frames;
}

/// Sends a multipart message; false when the socket's send timeout (ZMQ_SNDTIMEO) passed before
/// the first frame could be queued (a DEALER whose handshake was refused has no pipe to queue on).
inline bool send_message(zmq::socket_t& socket, const protocol::Message& frames) {
    for (std::size_t k = 0; k < frames.size(); ++k) {
        if (!socket.send(zmq::buffer(frames[k]),
                k + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none)) {
            return false;
        }
    }
    return true;
}

/// How long a test client's send may block: a refused peer must not hang the test.
inline constexpr int kTestSendTimeoutMs = 5000;

/// A DEALER client.
class Client {
public:
    Client(zmq::context_t& context, const std::string& endpoint, const std::string& identity = {})
        : m_socket(context, zmq::socket_type::dealer) {
        m_socket.set(zmq::sockopt::linger, 0);
        m_socket.set(zmq::sockopt::sndtimeo, kTestSendTimeoutMs);
        if (!identity.empty()) {
            m_socket.set(zmq::sockopt::routing_id, identity);
        }
        m_socket.connect(endpoint);
    }

    /// Sends raw frames and returns the reply frames (nullopt on timeout).
    std::optional<protocol::Message> raw(const protocol::Message& frames,
        std::chrono::milliseconds timeout = std::chrono::milliseconds(10000)) {
        if (!send_message(m_socket, frames)) {
            return std::nullopt;
        }
        return recv_message(m_socket, timeout);
    }

    /// Sends a request with a fresh integer id (or `id`) and decodes the reply.
    protocol::Reply call(const protocol::Params& params, protocol::EncodeOptions options = {},
        std::optional<protocol::RequestId> id = std::nullopt) {
        protocol::Request request { id ? *id : protocol::RequestId { ++m_next_id }, params };
        auto reply = raw(protocol::encode_request(request, options));
        if (!reply) {
            ADD_FAILURE() << "no reply to " << protocol::method_name(request.method());
            return {};
        }
        auto decoded = protocol::decode_reply(*reply, request.method());
        if (!decoded) {
            ADD_FAILURE() << "malformed reply: " << decoded.error().reason;
            return {};
        }
        return decoded.value();
    }

    /// Sends a notification (no reply expected).
    void notify(const protocol::Params& params) {
        send_message(
            m_socket, protocol::encode_request(protocol::Request { std::nullopt, params }));
    }

    /// The result of a call that must succeed, as type R.
    template <class R> R ok(const protocol::Params& params, protocol::EncodeOptions options = {}) {
        const protocol::Reply reply = call(params, options);
        if (!reply.ok()) {
            const auto& e = std::get<protocol::RpcError>(reply.outcome);
            ADD_FAILURE() << protocol::method_name(protocol::method_of(params))
                          << " failed: " << static_cast<int>(e.code) << " " << e.pointer << " "
                          << e.reason;
            return R {};
        }
        return std::get<R>(std::get<protocol::Result>(reply.outcome));
    }

    /// The error of a call that must fail.
    protocol::RpcError error(const protocol::Params& params, protocol::EncodeOptions options = {}) {
        const protocol::Reply reply = call(params, options);
        EXPECT_FALSE(reply.ok()) << protocol::method_name(protocol::method_of(params));
        if (reply.ok()) {
            return {};
        }
        return std::get<protocol::RpcError>(reply.outcome);
    }

    protocol::Stats stats() { return ok<protocol::Stats>(protocol::GetStatsParams {}); }

    zmq::socket_t& socket() { return m_socket; }

private:
    zmq::socket_t m_socket;
    std::int64_t m_next_id = 0;
};

/// Decodes an error reply given as raw frames.
inline protocol::RpcError error_of(const std::optional<protocol::Message>& reply) {
    if (!reply) {
        ADD_FAILURE() << "no reply";
        return {};
    }
    auto decoded = protocol::decode_reply(*reply, protocol::Method::Hello);
    if (!decoded || decoded->ok()) {
        ADD_FAILURE() << "not an error reply: " << reply->front();
        return {};
    }
    return std::get<protocol::RpcError>(decoded->outcome);
}

} // namespace polycut::server::testing
