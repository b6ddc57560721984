// A client presses the tissue with a tool through the live server (issue 15 item 1): it creates
// a probe, moves it down by notifications as an input device would, and reads the reaction
// force back from get_stats and from the stream header; bad tool requests are refused with a
// pointer and change nothing.
#include "server_fixture.hpp"

#include <cmath>

namespace polycut::server::testing {
namespace {

using namespace protocol;

class Tools : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };
};

std::optional<SurfaceFrame> next_surface(zmq::socket_t& sub) {
    for (int k = 0; k < 50; ++k) {
        const auto frames = recv_message(sub, std::chrono::milliseconds(10000));
        if (!frames) {
            return std::nullopt;
        }
        auto decoded = decode_stream(*frames);
        if (decoded && std::holds_alternative<SurfaceFrame>(decoded.value())) {
            return std::get<SurfaceFrame>(std::move(decoded).value());
        }
    }
    return std::nullopt;
}

TEST_F(Tools, ProbePressesTheTissueAndTheReactionComesBack) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    zmq::socket_t sub(context, zmq::socket_type::sub);
    sub.set(zmq::sockopt::linger, 0);
    sub.set(zmq::sockopt::rcvhwm, 10000);
    sub.connect(server.stream());
    sub.set(zmq::sockopt::subscribe, "surface");
    std::this_thread::sleep_for(std::chrono::milliseconds(200)); // slow joiner

    client.ok<RunState>(StepParams { 2 });
    ToolCreateParams create;
    create.shape = "sphere";
    create.radius = 0.012; // wider than the 1 cm node spacing: a stable contact patch
    create.position = { 0.0, 0.0, 0.033 };
    create.stiffness = 1e8;
    const auto tool = client.ok<Created>(create);
    EXPECT_EQ(tool.tick, 3);
    EXPECT_EQ(client.stats().tools, 1u);
    // Down 0.5 mm per tick, by notifications (the device rate), to 2.5 mm into the top.
    for (int k = 1; k <= 7; ++k) {
        client.notify(ToolMoveParams { tool.id, { 0.0, 0.0, 0.033 - 0.0005 * k }, std::nullopt });
        client.ok<RunState>(StepParams { 1 });
    }
    client.ok<RunState>(StepParams { 60 });
    const Stats stats = client.stats();
    ASSERT_EQ(stats.contacts.size(), 1u);
    const ContactReport& r = stats.contacts[0];
    EXPECT_EQ(r.kind, "tool");
    EXPECT_EQ(r.id, tool.id);
    EXPECT_GT(r.points, 0u);
    EXPECT_GT(r.force[2], 0.01); // the tissue pushes the probe up, tens of mN
    EXPECT_LT(std::hypot(r.force[0], r.force[1]), 0.1 * r.force[2]);
    EXPECT_GT(r.depth, 0.0);
    EXPECT_LT(r.depth, 0.0025);
    // The stream carries the same report in every frame header; the last one is this state.
    // A slow subscriber loses frames (docs/protocol.md, "Late joiners and gaps": the PUB's
    // high-water mark; a loaded machine can starve the subscriber's I/O thread during a burst
    // of 60 steps): if this tick's frame was lost, one more tick and its frame.
    std::optional<SurfaceFrame> frame;
    Stats at = stats;
    for (int attempt = 0; attempt < 5; ++attempt) {
        while ((frame = next_surface(sub)) && frame->header.tick < at.tick) { }
        if (frame && frame->header.tick == at.tick)
            break;
        client.ok<RunState>(StepParams { 1 });
        at = client.stats();
    }
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->header.tick, at.tick);
    ASSERT_EQ(frame->header.contacts.size(), 1u);
    ASSERT_EQ(at.contacts.size(), 1u);
    EXPECT_EQ(frame->header.contacts[0], at.contacts[0]);

    // Bad requests: pointer at the field, nothing changed.
    ToolCreateParams bad = create;
    bad.radius = std::nullopt;
    bad.shape = "blade";
    bad.size = Vector3 { 0.01, 0.0, 0.01 };
    EXPECT_EQ(client.error(bad).pointer, "/params/size/1");
    const RpcError unknown = client.error(ToolMoveParams { 999, { 0, 0, 0 }, std::nullopt });
    EXPECT_EQ(unknown.code, ErrorCode::NotFound);
    EXPECT_EQ(unknown.pointer, "/params/id");
    EXPECT_EQ(client.stats().tools, 1u);

    // Removed: no tool, no report.
    client.ok<Ack>(ToolRemoveParams { tool.id });
    client.ok<RunState>(StepParams { 1 });
    const Stats after = client.stats();
    EXPECT_EQ(after.tools, 0u);
    EXPECT_TRUE(after.contacts.empty());
    EXPECT_EQ(client.error(ToolRemoveParams { tool.id }).code, ErrorCode::NotFound);
}

} // namespace
} // namespace polycut::server::testing
