// Bad input never crashes the server and never changes its state (issue 6 item 5): each kind
// gets the documented JSON-RPC error with a JSON pointer, and the state hash reported by
// get_stats is the same before and after (the server is paused, so nothing else moves it).
// Also: a retried cut is applied once; a client that dies mid-message or mid-stroke leaves
// nothing behind.
#include "server_fixture.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace polycut::server::testing {
namespace {

using namespace protocol;

class BadInput : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };

    ServerConfig config() {
        ServerConfig c = test_config(dir, true);
        c.limits.max_frame_bytes = 64 * 1024;
        c.limits.max_triangles_per_cut = 16;
        return c;
    }
};

/// One bad request as raw frames and the error it must get.
struct Case {
    std::string name;
    Message frames;
    ErrorCode code;
    std::string pointer;
};

Message json_frame(const std::string& text) {
    return Message { text };
}

Message cut_frame_with(float bad_value) {
    std::vector<float> tris = { 0.0f, 0.003f, 0.03f, 0.01f, 0.003f, 0.03f, 0.0f, 0.003f, 0.01f };
    tris[5] = bad_value; // triangle 0, corner 1, z
    return Message { R"({"jsonrpc":"2.0","id":40,"method":"cut","params":{"triangles":)"
                     R"({"$frame":1,"dtype":"float32","shape":[1,3,3]}}})",
        encode_array(std::span<const float>(tris)) };
}

std::vector<Case> cases() {
    std::vector<Case> c;
    c.push_back({ "malformed JSON", json_frame(R"({"jsonrpc": "2.0", "id": 1, "method": )"),
        ErrorCode::ParseError, "" });
    c.push_back(
        { "invalid UTF-8", json_frame("{\"jsonrpc\":\"2.0\",\"id\":2,\"method\":\"he\xff\"}"),
            ErrorCode::ParseError, "" });
    c.push_back({ "number overflow",
        json_frame(
            R"({"jsonrpc":"2.0","id":3,"method":"apply_force","params":{"point":[0,0,1e999],"force":[0,0,-1],"radius":0.01}})"),
        ErrorCode::ParseError, "" });
    c.push_back({ "not an object", json_frame("[1, 2, 3]"), ErrorCode::InvalidRequest, "" });
    c.push_back({ "wrong jsonrpc", json_frame(R"({"jsonrpc":"1.0","id":5,"method":"hello"})"),
        ErrorCode::InvalidRequest, "/jsonrpc" });
    c.push_back({ "params not an object",
        json_frame(R"({"jsonrpc":"2.0","id":6,"method":"reset","params":[1]})"),
        ErrorCode::InvalidRequest, "/params" });
    c.push_back(
        { "unknown method", json_frame(R"({"jsonrpc":"2.0","id":7,"method":"Cut","params":{}})"),
            ErrorCode::MethodNotFound, "/method" });
    c.push_back({ "unknown param",
        json_frame(
            R"({"jsonrpc":"2.0","id":8,"method":"apply_force","params":{"point":[0,0,0.02],"force":[0,0,-1],"radius":0.01,"colour":"red"}})"),
        ErrorCode::InvalidParams, "/params/colour" });
    c.push_back({ "missing param",
        json_frame(
            R"({"jsonrpc":"2.0","id":9,"method":"apply_force","params":{"point":[0,0,0.02],"force":[0,0,-1]}})"),
        ErrorCode::InvalidParams, "/params/radius" });
    c.push_back({ "wrong type",
        json_frame(
            R"({"jsonrpc":"2.0","id":10,"method":"move_grab","params":{"id":1,"target":[0,0,"up"]}})"),
        ErrorCode::InvalidParams, "/params/target/2" });
    c.push_back({ "wrong array size",
        json_frame(R"({"jsonrpc":"2.0","id":11,"method":"grab","params":{"point":[0,0]}})"),
        ErrorCode::InvalidParams, "/params/point" });
    c.push_back({ "out of range",
        json_frame(
            R"({"jsonrpc":"2.0","id":12,"method":"apply_force","params":{"point":[0,0,0.02],"force":[0,0,-1],"radius":-1}})"),
        ErrorCode::InvalidParams, "/params/radius" });
    c.push_back({ "NaN in a float32 frame", cut_frame_with(std::numeric_limits<float>::quiet_NaN()),
        ErrorCode::InvalidParams, "/params/triangles/0/1/2" });
    c.push_back({ "Inf in a float32 frame", cut_frame_with(std::numeric_limits<float>::infinity()),
        ErrorCode::InvalidParams, "/params/triangles/0/1/2" });
    {
        Message m = cut_frame_with(0.03f);
        m[1].pop_back(); // 35 bytes instead of 36
        c.push_back(
            { "frame of the wrong length", m, ErrorCode::InvalidParams, "/params/triangles" });
    }
    {
        Message m = json_frame(R"({"jsonrpc":"2.0","id":14,"method":"hello"})");
        m.push_back("unreferenced");
        c.push_back({ "unreferenced frame", m, ErrorCode::InvalidRequest, "" });
    }
    c.push_back({ "degenerate triangle",
        json_frame(
            R"({"jsonrpc":"2.0","id":"cut-9","method":"cut","params":{"triangles":[[[0,0,0],[0.1,0,0],[0.2,0,0]]]}})"),
        ErrorCode::CutRejected, "/params/triangles/0" });
    // Geometry is judged once, where the cut is mapped (core/cut): the pointer names the
    // triangle, and the corner when one is to blame.
    c.push_back({ "coincident corners",
        json_frame(
            R"({"jsonrpc":"2.0","id":"cut-10","method":"cut","params":{"triangles":[[[0,0,0.01],[0.01,0,0.01],[0,0.01,0.01]],[[0,0,0],[0,0,0],[0,0.1,0]]]}})"),
        ErrorCode::CutRejected, "/params/triangles/1" });
    c.push_back({ "corner absurdly far",
        json_frame(
            R"({"jsonrpc":"2.0","id":"cut-11","method":"cut","params":{"triangles":[[[0,0,0.01],[0.01,0,0.01],[0,0.01,0.01]],[[0,0,0],[0,0.01,0],[0,0,200]]]}})"),
        ErrorCode::CutRejected, "/params/triangles/1/2" });
    c.push_back({ "empty cut",
        json_frame(R"({"jsonrpc":"2.0","id":16,"method":"cut","params":{"triangles":[]}})"),
        ErrorCode::InvalidParams, "/params/triangles" });
    {
        std::string tris;
        for (int k = 0; k < 17; ++k) {
            tris += std::string(k ? "," : "") + "[[0,0.003,0.03],[0.01,0.003,0.03],[0,0.003,0.01]]";
        }
        c.push_back({ "too many triangles",
            json_frame(R"({"jsonrpc":"2.0","id":17,"method":"cut","params":{"triangles":[)" + tris
                + "]}}"),
            ErrorCode::PayloadTooLarge, "/params/triangles" });
    }
    c.push_back({ "scene path",
        json_frame(
            R"({"jsonrpc":"2.0","id":18,"method":"load_scene","params":{"name":"../../etc/passwd"}})"),
        ErrorCode::InvalidParams, "/params/name" });
    c.push_back({ "unknown scene",
        json_frame(R"({"jsonrpc":"2.0","id":19,"method":"load_scene","params":{"name":"nope"}})"),
        ErrorCode::SceneError, "/params/name" });
    c.push_back({ "invalid inline scene",
        json_frame(
            R"({"jsonrpc":"2.0","id":20,"method":"load_scene","params":{"scene":{"name":"x","geometry":{"type":"box","size":[0.1,0.1,-1]}}}})"),
        ErrorCode::SceneError, "/params/scene/*" });
    c.push_back({ "inline scene naming a file outside",
        json_frame(
            R"({"jsonrpc":"2.0","id":21,"method":"load_scene","params":{"scene":{"geometry":{"type":"mesh","path":"/etc/passwd"},"method":"tet"}}})"),
        ErrorCode::SceneError, "" });
    c.push_back({ "blade endpoints coincide",
        json_frame(
            R"({"jsonrpc":"2.0","id":22,"method":"scalpel","params":{"stroke":1,"a":[0,0,0.03],"b":[0,0,0.03]}})"),
        ErrorCode::InvalidParams, "/params/b" });
    c.push_back({ "unknown force",
        json_frame(R"({"jsonrpc":"2.0","id":23,"method":"remove_force","params":{"id":99}})"),
        ErrorCode::NotFound, "/params/id" });
    c.push_back({ "unknown stroke",
        json_frame(R"({"jsonrpc":"2.0","id":24,"method":"end_stroke","params":{"stroke":5}})"),
        ErrorCode::NotFound, "/params/stroke" });
    c.push_back({ "step too many ticks",
        json_frame(R"({"jsonrpc":"2.0","id":25,"method":"step","params":{"ticks":1000000}})"),
        ErrorCode::InvalidParams, "/params/ticks" });
    c.push_back({ "rate too high",
        json_frame(R"({"jsonrpc":"2.0","id":26,"method":"set_rate","params":{"hz":1e6}})"),
        ErrorCode::InvalidParams, "/params/hz" });
    c.push_back({ "fractional id", json_frame(R"({"jsonrpc":"2.0","id":1.5,"method":"hello"})"),
        ErrorCode::InvalidRequest, "/id" });
    {
        Message m = json_frame(R"({"jsonrpc":"2.0","id":28,"method":"hello"})");
        for (int k = 0; k < 20; ++k) {
            m.push_back("x");
        }
        c.push_back({ "too many frames", m, ErrorCode::PayloadTooLarge, "" });
    }
    return c;
}

TEST_F(BadInput, EveryKindGetsItsErrorAndLeavesTheStateUnchanged) {
    RunningServer server(config());
    Client client(context, server.control());
    // Some state worth protecting: a force, a grab, an open stroke, a cut.
    client.ok<RunState>(StepParams { 3 });
    client.ok<Created>(ApplyForceParams { { 0, 0, 0.02 }, { 0, 0, -0.2 }, 0.01, std::nullopt });
    client.ok<Created>(GrabParams { { 0.01, 0.01, 0.02 }, 300.0, std::nullopt });
    client.ok<ScalpelResult>(
        ScalpelParams { 3, { -0.012, -0.007, 0.03 }, { -0.012, -0.007, 0.01 } });
    client.ok<CutResult>(CutParams { incision(0.003, -0.012, 0.012, 0.008) });
    const Stats before = client.stats();

    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const RpcError e = error_of(client.raw(c.frames));
        EXPECT_EQ(e.code, c.code) << e.reason;
        if (!c.pointer.empty() && c.pointer.back() == '*') {
            EXPECT_TRUE(e.pointer.starts_with(c.pointer.substr(0, c.pointer.size() - 1)))
                << e.pointer << ": " << e.reason;
        } else if (!c.pointer.empty()) {
            EXPECT_EQ(e.pointer, c.pointer) << e.reason;
        }
        EXPECT_FALSE(e.reason.empty());
        EXPECT_EQ(client.stats().state_hash, before.state_hash);
    }
    // A bad notification is not answered, but counted.
    const auto errors = client.stats().errors;
    send_message(client.socket(),
        json_frame(
            R"({"jsonrpc":"2.0","method":"scalpel","params":{"stroke":1,"a":[0,0,0],"b":[0,0,0]}})"));
    const Stats after = client.stats();
    EXPECT_EQ(after.errors, errors + 1);
    EXPECT_EQ(after.state_hash, before.state_hash);
    EXPECT_EQ(after.tick, before.tick);
    EXPECT_EQ(after.topology_version, before.topology_version);
    EXPECT_EQ(after.forces, before.forces);
    EXPECT_EQ(after.grabs, before.grabs);
    EXPECT_EQ(after.open_strokes, before.open_strokes);
}

TEST_F(BadInput, OversizeFrameDisconnectsOnlyThatPeer) {
    RunningServer server(config());
    Client client(context, server.control());
    const Stats before = client.stats();
    {
        Client big(context, server.control());
        const auto reply
            = big.raw(Message { std::string(100 * 1024, ' ') }, std::chrono::milliseconds(500));
        EXPECT_FALSE(reply.has_value()); // ZMQ_MAXMSGSIZE: dropped with the connection
    }
    const Stats after = client.stats();
    EXPECT_EQ(after.state_hash, before.state_hash);
    EXPECT_EQ(after.requests, before.requests + 1); // only the stats request itself
}

TEST_F(BadInput, RetriedCutIsAppliedOnce) {
    RunningServer server(config());
    Client observer(context, server.control());
    const CutParams cut { incision(0.003, -0.012, 0.012, 0.008) };
    Reply first;
    Stats after_first;
    {
        Client client(context, server.control(), "retrying-client");
        first = client.call(cut, {}, RequestId { std::string("cut-1") });
        ASSERT_TRUE(first.ok());
        after_first = observer.stats();
        // The same id again (a retry): the cached reply, and no second cut.
        const Reply retry = client.call(cut, {}, RequestId { std::string("cut-1") });
        EXPECT_EQ(retry, first);
        const Stats after_retry = observer.stats();
        EXPECT_EQ(after_retry.state_hash, after_first.state_hash);
        EXPECT_EQ(after_retry.topology_version, after_first.topology_version);
        EXPECT_GE(after_retry.cached_replies, 1u);
    }
    // A retry after a reconnect with the same routing identity hits the cache too.
    Client reconnected(context, server.control(), "retrying-client");
    const Reply again = reconnected.call(cut, {}, RequestId { std::string("cut-1") });
    EXPECT_EQ(again, first);
    EXPECT_EQ(observer.stats().state_hash, after_first.state_hash);
    // A fresh id cuts again.
    const Reply fresh = reconnected.call(CutParams { incision(0.013, -0.012, 0.012, 0.008) }, {},
        RequestId { std::string("cut-2") });
    ASSERT_TRUE(fresh.ok());
    EXPECT_GT(observer.stats().topology_version, after_first.topology_version);
}

TEST_F(BadInput, KilledClientLeavesNothingBehind) {
    ServerConfig c = config();
    c.client_ttl_s = 0.3;
    RunningServer server(c);
    Client client(context, server.control());
    const Stats before = client.stats();
    {
        // Dies in the middle of a multipart message: the ROUTER never delivers the part.
        zmq::socket_t dying(context, zmq::socket_type::dealer);
        dying.set(zmq::sockopt::linger, 0);
        dying.connect(server.control());
        const Message cut
            = encode_request(Request { RequestId { std::int64_t { 1 } },
                                 CutParams { incision(0.003, -0.012, 0.012, 0.008) } },
                EncodeOptions { true });
        dying.send(zmq::buffer(cut[0]), zmq::send_flags::sndmore);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        dying.close();
    }
    {
        // Dies with an open scalpel stroke and a cached reply.
        Client dying(context, server.control());
        dying.ok<ScalpelResult>(
            ScalpelParams { 1, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.01 } });
        dying.ok<Created>(ApplyForceParams { { 0, 0, 0.02 }, { 0, 0, -0.1 }, 0.01, 0.01 });
        EXPECT_EQ(client.stats().open_strokes, 1u);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    client.stats(); // keep this client alive
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    const Stats after = client.stats();
    EXPECT_EQ(after.open_strokes, 0u);
    EXPECT_EQ(after.cached_replies, 0u);
    EXPECT_EQ(after.client_states, 1u); // only `client`
    EXPECT_EQ(after.tick, before.tick);
    EXPECT_EQ(after.topology_version, before.topology_version); // the half-sent cut never ran
}

TEST_F(BadInput, FloodIsAnsweredBusy) {
    ServerConfig c = config();
    c.limits.max_message_rate = 20.0;
    RunningServer server(c);
    Client client(context, server.control());
    int busy = 0;
    for (int i = 0; i < 40; ++i) {
        const Reply r = client.call(GetStatsParams {});
        if (!r.ok() && std::get<RpcError>(r.outcome).code == ErrorCode::Busy) {
            ++busy;
        }
    }
    EXPECT_GT(busy, 0);
}

} // namespace
} // namespace polycut::server::testing
