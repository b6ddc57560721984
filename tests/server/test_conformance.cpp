// Conformance with docs/protocol.md on the points an independent client found wrong (issue 14
// item 5): integral float ids, NUL bytes in the JSON frame, forces and grabs far from the
// material, the method name in `rejected` events, and notifications that are never answered.
#include "server_fixture.hpp"

#include <nlohmann/json.hpp>

namespace polycut::server::testing {
namespace {

using namespace protocol;

class Conformance : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };

    /// A SUB socket on the event topic, known to be connected: bad notifications are sent until
    /// their `rejected` event arrives (slow joiner), then the socket is drained.
    zmq::socket_t events(RunningServer& server, Client& client) {
        zmq::socket_t sub(context, zmq::socket_type::sub);
        sub.set(zmq::sockopt::linger, 0);
        sub.connect(server.stream());
        sub.set(zmq::sockopt::subscribe, "event");
        for (int k = 0; k < 100; ++k) {
            send_message(client.socket(),
                Message { R"({"jsonrpc":"2.0","method":"hello","params":{"x":1}})" });
            if (recv_message(sub, std::chrono::milliseconds(50))) {
                break;
            }
        }
        while (recv_message(sub, std::chrono::milliseconds(100))) { }
        return sub;
    }
};

/// The detail object of the next `rejected` event (null json on timeout).
nlohmann::json next_rejected(zmq::socket_t& sub) {
    while (const auto frames = recv_message(sub, std::chrono::milliseconds(2000))) {
        auto decoded = decode_stream(*frames);
        if (!decoded) {
            continue;
        }
        if (const auto* e = std::get_if<Event>(&decoded.value()); e && e->kind == "rejected") {
            return nlohmann::json::parse(e->detail_json);
        }
    }
    return nullptr;
}

TEST_F(Conformance, AnIntegralFloatIdIsAnInteger) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    const auto reply = client.raw(Message { R"({"jsonrpc":"2.0","id":3.0,"method":"get_stats"})" });
    ASSERT_TRUE(reply.has_value());
    const auto j = nlohmann::json::parse(reply->front());
    EXPECT_TRUE(j.contains("result")) << reply->front();
    EXPECT_EQ(j["id"], 3);
    EXPECT_TRUE(j["id"].is_number_integer());
    // A fractional id is still -32600 at /id.
    const RpcError e
        = error_of(client.raw(Message { R"({"jsonrpc":"2.0","id":3.5,"method":"get_stats"})" }));
    EXPECT_EQ(e.code, ErrorCode::InvalidRequest);
    EXPECT_EQ(e.pointer, "/id");
}

TEST_F(Conformance, ANulByteInTheJsonFrameIsAParseErrorAndRunsNothing) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    client.ok<RunState>(StepParams { 3 });
    const Stats before = client.stats();
    // Valid JSON up to the NUL: before the fix this reset the scene (tick 3 -> 0).
    std::string text = R"({"jsonrpc":"2.0","id":7,"method":"reset"})";
    text += std::string("\0garbage", 8);
    const RpcError e = error_of(client.raw(Message { text }));
    EXPECT_EQ(e.code, ErrorCode::ParseError);
    EXPECT_NE(e.reason.find("NUL"), std::string::npos) << e.reason;
    const Stats after = client.stats();
    EXPECT_EQ(after.tick, before.tick);
    EXPECT_EQ(after.state_hash, before.state_hash);
}

TEST_F(Conformance, ForcesAndGrabsFarFromTheMaterialAreRefused) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    client.ok<RunState>(StepParams { 2 });
    const Stats before = client.stats();
    // The block spans [-0.02, 0.02]^2 x [0, 0.02] with 1 cm cells.
    RpcError e = client.error(ApplyForceParams { { 0, 0, 1.0 }, { 0, 0, -1 }, 0.01, std::nullopt });
    EXPECT_EQ(e.code, ErrorCode::SimulationError) << e.reason;
    EXPECT_EQ(e.pointer, "/params/point");
    e = client.error(GrabParams { { 5.0, 0, 0.01 }, 200.0, std::nullopt });
    EXPECT_EQ(e.code, ErrorCode::SimulationError) << e.reason;
    EXPECT_EQ(e.pointer, "/params/point");
    e = client.error(GrabParams { { 0, 0, 0.5 }, 200.0, 0.01 });
    EXPECT_EQ(e.code, ErrorCode::SimulationError) << e.reason;
    const Stats after = client.stats();
    EXPECT_EQ(after.forces, before.forces);
    EXPECT_EQ(after.grabs, before.grabs);
    EXPECT_EQ(after.state_hash, before.state_hash);
    // On or just off the surface (1 mm above the top, radius 2 mm; no radius) still works.
    client.ok<Created>(ApplyForceParams { { 0, 0, 0.021 }, { 0, 0, -0.1 }, 0.002, std::nullopt });
    client.ok<Created>(GrabParams { { 0.0201, 0.0201, 0.0201 }, 200.0, std::nullopt });
    EXPECT_EQ(client.stats().grabs, before.grabs + 1);
}

TEST_F(Conformance, RejectedEventsNameTheMethod) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    auto sub = events(server, client);
    // Rejected by the decoder (unknown param) and by the simulation (no material).
    send_message(client.socket(),
        Message {
            R"({"jsonrpc":"2.0","method":"apply_force","params":{"point":[0,0,0.02],"force":[0,0,-1],"radius":0.01,"colour":"red"}})" });
    nlohmann::json d = next_rejected(sub);
    ASSERT_FALSE(d.is_null());
    EXPECT_EQ(d["method"], "apply_force");
    EXPECT_EQ(d["code"], -32602);
    EXPECT_EQ(d["pointer"], "/params/colour");
    send_message(client.socket(), Message { R"({"jsonrpc":"2.0","method":"Cut","params":{}})" });
    d = next_rejected(sub);
    ASSERT_FALSE(d.is_null());
    EXPECT_EQ(d["method"], "Cut");
    EXPECT_EQ(d["code"], -32601);
    send_message(client.socket(),
        Message { R"({"jsonrpc":"2.0","method":"grab","params":{"point":[3,3,3]}})" });
    d = next_rejected(sub);
    ASSERT_FALSE(d.is_null());
    EXPECT_EQ(d["method"], "grab");
    EXPECT_EQ(d["code"], -32000);
}

TEST_F(Conformance, ANotificationWithAnUnreferencedFrameIsNotAnswered) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    auto sub = events(server, client);
    const Stats before = client.stats();
    const auto reply
        = client.raw(Message { R"({"jsonrpc":"2.0","method":"get_stats"})", "unreferenced" },
            std::chrono::milliseconds(300));
    EXPECT_FALSE(reply.has_value()) << reply->front();
    const nlohmann::json d = next_rejected(sub);
    ASSERT_FALSE(d.is_null());
    EXPECT_EQ(d["method"], "get_stats");
    EXPECT_EQ(d["code"], -32600);
    const Stats after = client.stats();
    EXPECT_EQ(after.errors, before.errors + 1);
    // A request (with an id) is still answered -32600.
    const RpcError e = error_of(
        client.raw(Message { R"({"jsonrpc":"2.0","id":1,"method":"get_stats"})", "unreferenced" }));
    EXPECT_EQ(e.code, ErrorCode::InvalidRequest);
}

} // namespace
} // namespace polycut::server::testing
