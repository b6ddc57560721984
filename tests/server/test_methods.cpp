// Every control method round-trips over tcp://127.0.0.1 against an in-process server, and each
// result says at which tick the command took effect (docs/protocol.md "Methods").
#include "server_fixture.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace polycut::server::testing {
namespace {

using namespace protocol;

class Methods : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };
};

TEST_F(Methods, HelloReportsProtocolLimitsAndStream) {
    ServerConfig config = test_config(dir, true);
    RunningServer server(config);
    Client client(context, server.control());
    const auto h = client.ok<HelloResult>(HelloParams { "test", "polycut/1" });
    EXPECT_EQ(h.protocol, "polycut/1");
    EXPECT_EQ(h.stream, server.stream());
    // The scene budget defaults to a share of the machine's memory; the rest as configured.
    EXPECT_GT(h.limits.max_scene_bytes, 0u);
    Limits expected = config.limits;
    expected.max_scene_bytes = h.limits.max_scene_bytes;
    EXPECT_EQ(h.limits, expected);
    EXPECT_FALSE(h.running);
    ASSERT_TRUE(h.scene.has_value());
    EXPECT_EQ(*h.scene, "small");
    for (const Method m : kAllMethods) {
        EXPECT_NE(std::find(h.capabilities.begin(), h.capabilities.end(), method_name(m)),
            h.capabilities.end())
            << method_name(m);
    }
    // A different protocol is refused at /params/protocol.
    const RpcError e = client.error(HelloParams { std::nullopt, "polycut/2" });
    EXPECT_EQ(e.code, ErrorCode::InvalidParams);
    EXPECT_EQ(e.pointer, "/params/protocol");
}

TEST_F(Methods, RunControlPauseStepResumeSetRate) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    const auto paused = client.ok<RunState>(PauseParams {});
    EXPECT_FALSE(paused.running);
    EXPECT_EQ(paused.tick, 0);
    // step N while paused: exactly N more ticks.
    const auto stepped = client.ok<RunState>(StepParams { 5 });
    EXPECT_EQ(stepped.tick, 5);
    EXPECT_FALSE(stepped.running);
    EXPECT_EQ(client.stats().tick, 5);
    const auto rate = client.ok<RunState>(SetRateParams { 120.0 });
    EXPECT_DOUBLE_EQ(rate.rate_hz, 120.0);
    // step while running is a state conflict.
    const auto resumed = client.ok<RunState>(ResumeParams {});
    EXPECT_TRUE(resumed.running);
    const RpcError e = client.error(StepParams { 1 });
    EXPECT_EQ(e.code, ErrorCode::StateConflict);
    // Resuming ticks on: the tick count grows.
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_GT(client.stats().tick, 5);
    const auto again = client.ok<RunState>(PauseParams {});
    EXPECT_FALSE(again.running);
    const auto reset = client.ok<RunState>(ResetParams {});
    EXPECT_EQ(reset.tick, 0);
    EXPECT_EQ(client.stats().tick, 0);
}

TEST_F(Methods, ForcesAndGrabsCreateIdsAndTakeEffectNextTick) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    client.ok<RunState>(StepParams { 2 });
    ApplyForceParams f;
    f.point = { 0.0, 0.0, 0.02 };
    f.force = { 0.0, 0.0, -0.5 };
    f.radius = 0.01;
    const auto force = client.ok<Created>(f);
    EXPECT_GE(force.id, 1u);
    EXPECT_EQ(force.tick, 3); // the first frame that reflects it
    EXPECT_EQ(client.stats().forces, 1u);
    // A force with a duration disappears by itself.
    f.duration = 0.02;
    const auto brief = client.ok<Created>(f);
    EXPECT_NE(brief.id, force.id);
    EXPECT_EQ(client.stats().forces, 2u);
    client.ok<RunState>(StepParams { 3 });
    EXPECT_EQ(client.stats().forces, 1u);
    EXPECT_EQ(client.error(RemoveForceParams { brief.id }).code, ErrorCode::NotFound);
    EXPECT_EQ(client.ok<Ack>(RemoveForceParams { force.id }).tick, 6);
    EXPECT_EQ(client.stats().forces, 0u);
    EXPECT_EQ(client.error(RemoveForceParams { force.id }).code, ErrorCode::NotFound);

    GrabParams g;
    g.point = { 0.02, 0.0, 0.02 };
    g.stiffness = 400.0;
    const auto grab = client.ok<Created>(g);
    EXPECT_EQ(client.stats().grabs, 1u);
    const std::string before = client.stats().state_hash;
    EXPECT_EQ(client.ok<Ack>(MoveGrabParams { grab.id, { 0.03, 0.0, 0.025 } }).tick, 6);
    EXPECT_NE(client.stats().state_hash, before); // the anchor is part of the state
    client.ok<RunState>(StepParams { 10 });
    EXPECT_EQ(client.ok<Ack>(ReleaseParams { grab.id }).tick, 16);
    EXPECT_EQ(client.stats().grabs, 0u);
    const RpcError e = client.error(MoveGrabParams { grab.id, { 0.0, 0.0, 0.0 } });
    EXPECT_EQ(e.code, ErrorCode::NotFound);
    EXPECT_EQ(e.pointer, "/params/id");
}

TEST_F(Methods, LoadSceneByNameAndInline) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    client.ok<RunState>(StepParams { 3 });
    LoadSceneParams by_name;
    by_name.name = "small";
    const auto loaded = client.ok<SceneResult>(by_name);
    EXPECT_EQ(loaded.name, "small");
    EXPECT_EQ(loaded.tick, 0);
    EXPECT_EQ(loaded.cell_count, 4u * 4u * 2u * 6u);
    EXPECT_GT(loaded.vertex_count, 0u);
    EXPECT_GT(loaded.triangle_count, 0u);
    EXPECT_EQ(client.stats().tick, 0);
    // What the scene built (sim build report): the parts a dynamic tet block needs, in build
    // order, and the cut pipeline the server prepares at load; nothing it does not need.
    std::vector<std::string> parts;
    for (const SceneResult::BuildPart& p : loaded.build_parts) {
        parts.push_back(p.name);
        EXPECT_TRUE(std::isfinite(p.ms) && p.ms >= 0) << p.name;
        EXPECT_GE(p.rss_kb, 0) << p.name;
    }
    EXPECT_EQ(
        parts, (std::vector<std::string> { "mesh", "model", "integrator", "surface", "cut" }));

    LoadSceneParams inline_scene;
    inline_scene.scene_json = kSmallScene;
    const auto inl = client.ok<SceneResult>(inline_scene);
    EXPECT_EQ(inl.name, "inline");
    EXPECT_EQ(inl.cell_count, loaded.cell_count);
    EXPECT_EQ(inl.triangle_count, loaded.triangle_count);
}

TEST_F(Methods, CutInlineAndBinaryFramesChangeTopology) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    const auto before = client.stats();
    CutParams cut { incision(0.003, -0.012, 0.012, 0.008) };
    const auto r = client.ok<CutResult>(cut);
    EXPECT_EQ(r.triangles, 2u);
    EXPECT_EQ(r.tick, 1);
    EXPECT_GT(r.topology_version, before.topology_version);
    // The same kind of cut as a float32 frame.
    CutParams second { incision(0.013, -0.012, 0.012, 0.008) };
    const auto r2 = client.ok<CutResult>(second, EncodeOptions { true });
    EXPECT_EQ(r2.triangles, 2u);
    EXPECT_GT(r2.topology_version, r.topology_version);
    // get_stats reports the cuts in rest space (docs/protocol.md): none before; after, the two
    // 2.4 x 1.2 cm incisions swept 2 x 2.88 cm^2 inside the block (the server was paused: the
    // blade met the block at rest). Face snapping rounds these to the 1 cm cells' whole faces.
    EXPECT_EQ(before.cut_area, 0.0);
    EXPECT_EQ(before.swept_area, 0.0);
    EXPECT_EQ(before.cut_completeness, 0.0);
    const auto after = client.stats();
    EXPECT_NEAR(after.swept_area, 2 * 0.024 * 0.012, 1e-9);
    EXPECT_GT(after.cut_area, 0.0);
    EXPECT_NEAR(after.cut_completeness, after.cut_area / (2 * after.swept_area), 1e-12);
    // Cell splitting follows the blade: the same incision opens twice its swept area, within
    // the 1 % of issue 12 item 4, as get_stats reports it.
    std::string split = kSmallScene;
    split.replace(
        split.find(R"("method": "tet")"), 15, R"("method": "mvc", "cutting": {"method": "split"})");
    LoadSceneParams load;
    load.scene_json = split;
    client.ok<SceneResult>(load);
    EXPECT_EQ(client.stats().swept_area, 0.0);
    client.ok<CutResult>(CutParams { incision(0.003, -0.012, 0.012, 0.008) });
    const auto split_stats = client.stats();
    EXPECT_NEAR(split_stats.swept_area, 0.024 * 0.012, 1e-9);
    EXPECT_NEAR(split_stats.cut_completeness, 1.0, 0.01);
}

TEST_F(Methods, ScalpelStrokeFormsSweepTrianglesAndEndStrokeCloses) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    const std::uint64_t v0 = client.stats().topology_version;
    // Three blade samples along y = 0: the first opens the stroke, each next adds two triangles
    // per quad. A move longer than the mean cell size (Simulation::blade_max_advance: the cube
    // root of a Kuhn tet's volume, (1 cm^3 / 6)^(1/3) = 5.5 mm on the small block) is swept in
    // equal quads of at most that: 12 mm -> 3 quads, 6 triangles.
    const auto s0 = client.ok<ScalpelResult>(
        ScalpelParams { 7, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } });
    EXPECT_EQ(s0.triangles, 0u);
    EXPECT_EQ(client.stats().open_strokes, 1u);
    const auto s1 = client.ok<ScalpelResult>(
        ScalpelParams { 7, { 0.0, 0.003, 0.03 }, { 0.0, 0.003, 0.008 } });
    EXPECT_EQ(s1.triangles, 6u);
    // The blade did not move: degenerate sweep, skipped.
    const auto s2 = client.ok<ScalpelResult>(
        ScalpelParams { 7, { 0.0, 0.003, 0.03 }, { 0.0, 0.003, 0.008 } });
    EXPECT_EQ(s2.triangles, 0u);
    client.notify(ScalpelParams { 7, { 0.012, 0.003, 0.03 }, { 0.012, 0.003, 0.008 } });
    const auto end = client.ok<CutResult>(EndStrokeParams { 7 });
    EXPECT_EQ(end.triangles, 12u);
    EXPECT_GT(end.topology_version, v0);
    // The quads tile the blade's sweep: inside the block (z 0.8-2 cm) it swept 2.4 x 1.2 cm.
    EXPECT_NEAR(client.stats().swept_area, 0.024 * 0.012, 1e-9);
    EXPECT_EQ(client.stats().open_strokes, 0u);
    const RpcError e = client.error(EndStrokeParams { 7 });
    EXPECT_EQ(e.code, ErrorCode::NotFound);
    EXPECT_EQ(e.pointer, "/params/stroke");
}

TEST_F(Methods, GetSurfaceAndStatsDescribeTheSameSurface) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    client.ok<RunState>(StepParams { 4 });
    const auto snap = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
    const auto stats = client.stats();
    EXPECT_EQ(snap.header.tick, 4);
    EXPECT_EQ(snap.header.seq, stats.seq);
    EXPECT_TRUE(snap.header.has_topology);
    EXPECT_EQ(snap.positions.size(), 3u * snap.header.vertex_count);
    EXPECT_EQ(snap.triangles.size(), 3u * snap.header.triangle_count);
    EXPECT_EQ(snap.tags.size(), snap.header.triangle_count);
    EXPECT_EQ(stats.vertex_count, snap.header.vertex_count);
    EXPECT_EQ(stats.triangle_count, snap.header.triangle_count);
    EXPECT_EQ(stats.cell_count, 4u * 4u * 2u * 6u);
    EXPECT_EQ(stats.state_hash.size(), 16u);
    // Under gravity the top sags: some vertex is below its rest height 0.02 m.
    float top = -1;
    for (std::size_t i = 2; i < snap.positions.size(); i += 3) {
        top = std::max(top, snap.positions[i]);
    }
    EXPECT_LT(top, 0.02f);
    EXPECT_GT(top, 0.019f);
}

TEST_F(Methods, ShutdownRepliesAndStopsTheLoop) {
    RunningServer server(test_config(dir, false));
    Client client(context, server.control());
    const auto ack = client.ok<Ack>(ShutdownParams {});
    EXPECT_GE(ack.tick, 0);
    EXPECT_TRUE(server.wait_stopped(std::chrono::milliseconds(5000)));
}

TEST_F(Methods, ReqSocketsWorkToo) {
    RunningServer server(test_config(dir, true));
    zmq::socket_t req(context, zmq::socket_type::req);
    req.set(zmq::sockopt::linger, 0);
    req.connect(server.control());
    send_message(req, encode_request(Request { RequestId { std::int64_t { 1 } }, HelloParams {} }));
    const auto reply = recv_message(req, std::chrono::milliseconds(10000));
    ASSERT_TRUE(reply.has_value());
    const auto decoded = decode_reply(*reply, Method::Hello);
    ASSERT_TRUE(decoded.ok());
    EXPECT_TRUE(decoded->ok());
}

} // namespace
} // namespace polycut::server::testing
