// A cut that cannot be applied never ends the service (issue 12 item 1): for each way a client
// cuts — `cut`, `end_stroke`, a `scalpel` request and `scalpel` notifications at the tick — a cut
// made to fail (cut::inject_cut_failures: the cutter edits the mesh, then throws) is undone, the
// client hears about it (a -32002 error, or a `rejected` event naming the stroke), the state is as
// before, and the server goes on answering and cutting. Both cutters (`tet` snap, `mvc` split).
#include "polycut/cut/fault_injection.hpp"
#include "server_fixture.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace polycut::server::testing {
namespace {

using namespace protocol;

/// The small block as `mvc` with the splitting cutter.
std::string split_scene() {
    nlohmann::json scene = nlohmann::json::parse(kSmallScene);
    scene["method"] = "mvc";
    scene["cutting"] = { { "method", "split" } };
    return scene.dump();
}

class CutFailures : public ::testing::TestWithParam<bool> {
protected:
    void SetUp() override {
        server = std::make_unique<RunningServer>(test_config(dir, true));
        client = std::make_unique<Client>(context, server->control());
        if (GetParam()) {
            LoadSceneParams load;
            load.scene_json = split_scene();
            client->ok<SceneResult>(load);
        }
    }
    void TearDown() override { cut::inject_cut_failures(0); }

    /// A subscriber to the whole stream, connected before the test's commands.
    zmq::socket_t subscribe() {
        zmq::socket_t sub(context, zmq::socket_type::sub);
        sub.set(zmq::sockopt::linger, 0);
        sub.set(zmq::sockopt::rcvhwm, 10000);
        sub.connect(server->stream());
        sub.set(zmq::sockopt::subscribe, "");
        std::this_thread::sleep_for(std::chrono::milliseconds(200)); // the subscription travels
        return sub;
    }

    /// What the stream said until it fell silent for half a second.
    struct Heard {
        std::optional<nlohmann::json> rejected; ///< detail of the last `rejected` event
        std::optional<SurfaceFrame> last; ///< the last surface frame
    };
    static Heard listen(zmq::socket_t& sub) {
        Heard heard;
        for (int k = 0; k < 40; ++k) {
            const auto frames = recv_message(sub, std::chrono::milliseconds(500));
            if (!frames) {
                break;
            }
            auto decoded = decode_stream(*frames);
            EXPECT_TRUE(decoded.ok());
            if (!decoded) {
                break;
            }
            if (const auto* e = std::get_if<Event>(&decoded.value()); e && e->kind == "rejected") {
                heard.rejected = nlohmann::json::parse(e->detail_json);
            } else if (const auto* f = std::get_if<SurfaceFrame>(&decoded.value())) {
                heard.last = *f;
            }
        }
        return heard;
    }

    SceneDir dir;
    zmq::context_t context { 1 };
    std::unique_ptr<RunningServer> server;
    std::unique_ptr<Client> client;
};

TEST_P(CutFailures, CutRequestGetsAnErrorAndNothingChanges) {
    const Stats before = client->stats();
    cut::inject_cut_failures(1);
    const RpcError e = client->error(CutParams { incision(0.003, -0.012, 0.012, 0.008) });
    EXPECT_EQ(e.code, ErrorCode::CutRejected);
    EXPECT_NE(e.reason.find("undone"), std::string::npos) << e.reason;
    const Stats after = client->stats();
    EXPECT_EQ(after.state_hash, before.state_hash);
    EXPECT_EQ(after.topology_version, before.topology_version);
    EXPECT_EQ(after.cell_count, before.cell_count);
    // The blade swept tissue it did not cut: get_stats counts it as swept and undone.
    EXPECT_EQ(after.swept_area, before.swept_area);
    EXPECT_GT(after.swept_area_undone, 0.0);
    // The same cut goes through once nothing is armed.
    const auto ok = client->ok<CutResult>(CutParams { incision(0.003, -0.012, 0.012, 0.008) });
    EXPECT_GT(ok.topology_version, before.topology_version);
    // The applied cut swept what the failed one did (the same triangles, the same tissue), and
    // the completeness divides by both: half what the applied cut alone would give.
    const Stats done = client->stats();
    EXPECT_NEAR(done.swept_area, after.swept_area_undone, 1e-12);
    EXPECT_GT(done.cut_area, 0.0);
    EXPECT_NEAR(done.cut_completeness, 0.5 * done.cut_area / (2 * done.swept_area), 1e-12);
}

TEST_P(CutFailures, EndStrokeGetsAnErrorAndTheStrokeIsClosed) {
    const Stats before = client->stats();
    client->notify(ScalpelParams { 3, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } });
    client->notify(ScalpelParams { 3, { 0.012, 0.003, 0.03 }, { 0.012, 0.003, 0.008 } });
    cut::inject_cut_failures(1);
    const RpcError e = client->error(EndStrokeParams { 3 });
    EXPECT_EQ(e.code, ErrorCode::CutRejected);
    const Stats after = client->stats();
    EXPECT_EQ(after.topology_version, before.topology_version);
    EXPECT_EQ(after.cell_count, before.cell_count);
    EXPECT_EQ(after.open_strokes, 0u);
}

TEST_P(CutFailures, ScalpelRequestGetsAnErrorAndTheSampleIsTakenBack) {
    const Stats before = client->stats();
    const ScalpelParams first { 5, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } };
    const ScalpelParams second { 5, { 0.012, 0.003, 0.03 }, { 0.012, 0.003, 0.008 } };
    EXPECT_EQ(client->ok<ScalpelResult>(first).triangles, 0u);
    cut::inject_cut_failures(1);
    const RpcError e = client->error(second);
    EXPECT_EQ(e.code, ErrorCode::CutRejected);
    EXPECT_EQ(client->stats().topology_version, before.topology_version);
    // The stroke still continues from the first sample: resending the second one cuts (a 24 mm
    // move on 5.5 mm cells: 5 quads, Simulation::blade_max_advance).
    EXPECT_EQ(client->ok<ScalpelResult>(second).triangles, 10u);
    EXPECT_GT(client->stats().topology_version, before.topology_version);
    EXPECT_EQ(client->ok<CutResult>(EndStrokeParams { 5 }).triangles, 10u);
}

TEST_P(CutFailures, ScalpelNotificationsAtTheTickPublishARejectedEvent) {
    zmq::socket_t sub = subscribe();
    const Stats before = client->stats();
    client->notify(ScalpelParams { 9, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } });
    client->notify(ScalpelParams { 9, { 0.012, 0.003, 0.03 }, { 0.012, 0.003, 0.008 } });
    cut::inject_cut_failures(1);
    client->ok<RunState>(StepParams { 2 }); // the queued sweep is cut at the first tick
    const std::optional<nlohmann::json> rejected = listen(sub).rejected;
    ASSERT_TRUE(rejected.has_value()) << "no rejected event";
    EXPECT_EQ((*rejected)["method"], "scalpel");
    EXPECT_EQ((*rejected)["stroke"], 9);
    EXPECT_EQ((*rejected)["code"], static_cast<int>(ErrorCode::CutRejected));
    EXPECT_EQ((*rejected)["triangles"], 10); // 24 mm on 5.5 mm cells: 5 quads
    const Stats after = client->stats();
    EXPECT_EQ(after.topology_version, before.topology_version);
    EXPECT_EQ(after.tick, before.tick + 2); // the server stepped on
    // The stroke is still open and cuts on (back over the same path: the uncut one).
    client->notify(ScalpelParams { 9, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } });
    EXPECT_EQ(client->ok<CutResult>(EndStrokeParams { 9 }).triangles, 20u);
    EXPECT_GT(client->stats().topology_version, before.topology_version);
}

TEST_P(CutFailures, ACutWhoseStepExplodesIsUndoneAndItsStrokeHearsIt) {
    // The stroke is cut when the grab request flushes it; the 1e9 N/m grab pulled 1 m away then
    // makes the next step explode: that step undoes the cut, and the stroke gets a rejected
    // event. The published frame is the uncut block (new topology version), bounded.
    zmq::socket_t sub = subscribe();
    const Stats before = client->stats();
    client->notify(ScalpelParams { 4, { -0.012, 0.003, 0.03 }, { -0.012, 0.003, 0.008 } });
    client->notify(ScalpelParams { 4, { 0.012, 0.003, 0.03 }, { 0.012, 0.003, 0.008 } });
    GrabParams g;
    g.point = { 0.02, 0.02, 0.02 };
    g.stiffness = 1e9;
    const auto grab = client->ok<Created>(g);
    EXPECT_GT(client->stats().topology_version, before.topology_version); // the cut is in
    client->ok<Ack>(MoveGrabParams { grab.id, { 1.0, 0.02, 0.02 } });
    client->ok<RunState>(StepParams { 1 });
    const Heard heard = listen(sub);
    const std::optional<nlohmann::json>& rejected = heard.rejected;
    const std::optional<SurfaceFrame>& last = heard.last;
    ASSERT_TRUE(rejected.has_value()) << "no rejected event";
    EXPECT_EQ((*rejected)["stroke"], 4);
    EXPECT_NE((*rejected)["reason"].get<std::string>().find("undone"), std::string::npos);
    const Stats after = client->stats();
    EXPECT_EQ(after.cell_count, before.cell_count); // uncut again
    EXPECT_NE(after.topology_version, before.topology_version);
    ASSERT_TRUE(last.has_value());
    for (float x : last->positions) {
        EXPECT_TRUE(std::isfinite(x));
        EXPECT_LT(std::abs(x), 0.1f); // the 4 cm block, not the exploded step
    }
}

INSTANTIATE_TEST_SUITE_P(BothCutters, CutFailures, ::testing::Values(false, true),
    [](const ::testing::TestParamInfo<bool>& param) {
        return param.param ? std::string("MvcSplit") : std::string("TetSnap");
    });

} // namespace
} // namespace polycut::server::testing
