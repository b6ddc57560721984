// Replies: every result type and the error object round-trip through encode/decode.
#include "polycut/protocol/reply.hpp"

#include <gtest/gtest.h>

namespace polycut::protocol {
namespace {

Result sample_result(Method method) {
    switch (result_index(method)) {
    case 0: {
        HelloResult h;
        h.server = "polycut-server 0.1.0";
        h.capabilities = { "hello", "cut", "binary_frames" };
        h.stream = "tcp://127.0.0.1:5556";
        h.tick = 12;
        h.running = true;
        h.scene = "cut_halves";
        h.limits.max_triangles_per_cut = 100;
        return h;
    }
    case 1:
        return SceneResult { 0, "cut_halves", 1, 386, 768, 1200, 3120, 41.5,
            { { "mesh", 3.5, 120 }, { "model", 1.25, 2048 }, { "integrator", 0.0, 0 } } };
    case 2:
        return RunState { 99, method == Method::Resume, 120.0 };
    case 3:
        return Ack { 100 };
    case 4:
        return Created { 5, 101 };
    case 5:
        return CutResult { 102, 4, 18 };
    case 6:
        return ScalpelResult { 103, 2 };
    case 7: {
        SurfaceSnapshot s;
        s.header.seq = 55;
        s.header.tick = 54;
        s.header.sim_time = 0.9;
        s.header.topology_version = 3;
        s.header.has_topology = true;
        s.header.vertex_count = 3;
        s.header.triangle_count = 1;
        s.header.step.solver_iterations = 2;
        s.positions = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
        s.triangles = { 0, 1, 2 };
        s.tags = { 2 };
        return s;
    }
    default: {
        Stats s;
        s.tick = 600;
        s.sim_time = 10.0;
        s.seq = 600;
        s.ticks_over_budget = 3;
        s.worst_tick_ms = 21.5;
        s.step_ms_p50 = 4.0;
        s.step_ms_p99 = 9.5;
        s.requests = 1000;
        s.errors = 2;
        s.clients = 1;
        return s;
    }
    }
}

TEST(ProtocolReply, EveryMethodResultRoundTrips) {
    for (Method method : kAllMethods) {
        SCOPED_TRACE(std::string(method_name(method)));
        const Result result = sample_result(method);
        const RequestId id = std::int64_t { 9 };
        const Message m = encode_result(id, result);
        EXPECT_EQ(m.size(), method == Method::GetSurface ? 4u : 1u);
        const auto d = decode_reply(m, method);
        ASSERT_TRUE(d.ok()) << d.error().pointer << ": " << d.error().reason << "\n" << m[0];
        ASSERT_TRUE(d->ok());
        EXPECT_EQ(d->id, id);
        EXPECT_EQ(std::get<Result>(d->outcome), result);
        auto peeked = peek_reply_id(m[0]);
        ASSERT_TRUE(peeked.ok());
        EXPECT_EQ(peeked.value(), id);
    }
}

TEST(ProtocolReply, ErrorRoundTripsWithPointer) {
    const RpcError error = make_error(ErrorCode::NotFound, "/params/id", "no force with id 77");
    const Message m = encode_error(std::string("r1"), error);
    ASSERT_EQ(m.size(), 1u);
    EXPECT_NE(m[0].find(R"("code":-32003)"), std::string::npos) << m[0];
    const auto d = decode_reply(m, Method::RemoveForce);
    ASSERT_TRUE(d.ok());
    EXPECT_FALSE(d->ok());
    EXPECT_EQ(std::get<RpcError>(d->outcome), error);
}

TEST(ProtocolReply, MalformedRepliesAreReported) {
    EXPECT_FALSE(decode_reply(Message { R"({"jsonrpc":"2.0","id":1})" }, Method::Reset).ok());
    EXPECT_FALSE(decode_reply(
        Message { R"({"jsonrpc":"2.0","id":1,"result":{},"error":{}})" }, Method::Reset)
                     .ok());
    const auto missing
        = decode_reply(Message { R"({"jsonrpc":"2.0","id":1,"result":{}})" }, Method::Reset);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().pointer, "/result/tick");
    // Unknown result members are tolerated (forward compatibility).
    EXPECT_TRUE(decode_reply(
        Message { R"({"jsonrpc":"2.0","id":1,"result":{"tick":3,"new":1}})" }, Method::Release)
                    .ok());
}

} // namespace
} // namespace polycut::protocol
