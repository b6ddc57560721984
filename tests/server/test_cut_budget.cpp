// The cut budget (issue 12 item 5, docs/protocol.md "The cut budget"): the cuts of one tick change
// at most cutting.max_cells_per_tick cells; a `cut` past it is answered at once with the part
// applied and the part `deferred`, the rest is cut over the next ticks (each frame's header says
// how many triangles wait), a stroke whose end_stroke came while triangles of it waited is
// finished once they are cut, and the end result is the cut without a budget. Both cutters.
#include "polycut/common/types.hpp"
#include "server_fixture.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace polycut::server::testing {
namespace {

using namespace protocol;

/// The small block with `budget` cells per tick; `split`: `mvc` with the splitting cutter.
std::string scene(bool split, int budget) {
    nlohmann::json s = nlohmann::json::parse(kSmallScene);
    if (split) {
        s["method"] = "mvc";
        s["cutting"] = { { "method", "split" } };
    }
    s["cutting"]["max_cells_per_tick"] = budget;
    return s.dump();
}

/// An incision along x through the whole block at y = 3 mm in `n` strips: 2 n triangles.
std::vector<Triangle3> long_incision(int n) {
    std::vector<Triangle3> out;
    for (int k = 0; k < n; ++k) {
        const double x0 = -0.025 + 0.05 * k / n, x1 = -0.025 + 0.05 * (k + 1) / n;
        for (const Triangle3& t : incision(0.003, x0, x1, 0.006)) {
            out.push_back(t);
        }
    }
    return out;
}

/// Area of the triangles tagged 2 (cut surface) of a snapshot [m^2].
double cut_area(const SurfaceFrame& s) {
    double area = 0;
    for (std::size_t t = 0; t < s.tags.size(); ++t) {
        if (s.tags[t] != 2) {
            continue;
        }
        polycut::Vec3 p[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = s.triangles[3 * t + std::size_t(k)];
            p[k]
                = polycut::Vec3(s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]);
        }
        area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    }
    return area;
}

class CutBudget : public ::testing::TestWithParam<bool> {
protected:
    void SetUp() override {
        server = std::make_unique<RunningServer>(test_config(dir, true));
        client = std::make_unique<Client>(context, server->control());
    }
    void load(int budget) {
        LoadSceneParams p;
        p.scene_json = scene(GetParam(), budget);
        client->ok<SceneResult>(p);
    }
    /// Steps one tick at a time until nothing waits (at most `max` ticks); returns the ticks.
    int drain(int max) {
        for (int k = 1; k <= max; ++k) {
            client->ok<RunState>(StepParams { 1 });
            if (client->ok<SurfaceSnapshot>(GetSurfaceParams {}).header.cut_deferred == 0) {
                return k;
            }
        }
        return max + 1;
    }
    SceneDir dir;
    zmq::context_t context { 1 };
    std::unique_ptr<RunningServer> server;
    std::unique_ptr<Client> client;
};

TEST_P(CutBudget, ALongCutIsSpreadOverTicksAndCutsWhatItWouldWithoutABudget) {
    const std::vector<Triangle3> tris = long_incision(8);
    // Without a budget: the reference.
    load(0);
    const CutResult whole = client->ok<CutResult>(CutParams { tris });
    EXPECT_EQ(whole.triangles, tris.size());
    EXPECT_EQ(whole.deferred, 0u);
    client->ok<RunState>(StepParams { 1 }); // the snapshot is the last published frame
    const double reference = cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {}));
    ASSERT_GT(reference, 0.0);

    // With 6 cells per tick.
    load(6);
    const CutResult first = client->ok<CutResult>(CutParams { tris });
    EXPECT_GE(first.triangles, 1u);
    EXPECT_GT(first.deferred, 0u) << "6 cells per tick should not hold the whole incision";
    EXPECT_EQ(first.triangles + first.deferred, tris.size());
    const int ticks = drain(200);
    EXPECT_GE(ticks, 2) << "the rest should need more than one more tick";
    EXPECT_LE(ticks, 200) << "the deferred triangles were never cut";
    // The surface is the same incision (the block sags a little between the ticks: 3 %).
    const double area = cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {}));
    EXPECT_NEAR(area / reference, 1.0, 0.03);
    EXPECT_EQ(client->stats().open_strokes, 0u);
}

TEST_P(CutBudget, AStrokeEndedWhileItsTrianglesWaitIsFinishedLater) {
    load(4);
    const Stats before = client->stats();
    for (int k = 0; k <= 8; ++k) {
        const double x = -0.025 + 0.05 * k / 8;
        client->notify(ScalpelParams { 7, { x, 0.003, 0.03 }, { x, 0.003, 0.006 } });
    }
    const CutResult end = client->ok<CutResult>(EndStrokeParams { 7 });
    EXPECT_GT(end.deferred, 0u);
    EXPECT_EQ(client->stats().open_strokes, 0u); // closed for the client at once
    EXPECT_LE(drain(200), 200);
    const Stats after = client->stats();
    EXPECT_GT(after.topology_version, before.topology_version);
    EXPECT_GT(cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {})), 0.0);
    // The same stroke id is free again and cuts.
    client->notify(ScalpelParams { 7, { -0.025, -0.005, 0.03 }, { -0.025, -0.005, 0.01 } });
    client->notify(ScalpelParams { 7, { 0.025, -0.005, 0.03 }, { 0.025, -0.005, 0.01 } });
    client->ok<CutResult>(EndStrokeParams { 7 });
    EXPECT_LE(drain(200), 200);
}

TEST_P(CutBudget, AFastBladeIsSweptInCellSizedQuadsThatTheBudgetSpreads) {
    // One scalpel move along the whole block (5 cm in one sample) is swept as ceil(5 cm / 5.5
    // mm) = 10 quads (Simulation::blade_max_advance: the cube root of a Kuhn tet's volume,
    // (1 cm^3 / 6)^(1/3)). The quads tile the move: the swept area of one quad cut at once.
    // A budget of 6 cells per tick spreads them over more ticks, like a long `cut`, and the
    // stroke then cuts what it cuts without the budget.
    load(0);
    client->ok<CutResult>(CutParams { incision(0.003, -0.025, 0.025, 0.006) });
    const double swept = client->stats().swept_area;
    EXPECT_NEAR(swept, 0.04 * 0.014, 1e-9); // inside the block: x -2-2 cm, z 0.6-2 cm

    const auto stroke = [&] {
        client->notify(ScalpelParams { 2, { -0.025, 0.003, 0.03 }, { -0.025, 0.003, 0.006 } });
        client->notify(ScalpelParams { 2, { 0.025, 0.003, 0.03 }, { 0.025, 0.003, 0.006 } });
        return client->ok<CutResult>(EndStrokeParams { 2 });
    };
    // No cell budget (the server's 16 triangles per tick still apply: 16 + 4).
    load(0);
    const CutResult whole = stroke();
    EXPECT_EQ(whole.triangles + whole.deferred, 20u);
    EXPECT_LE(drain(10), 10);
    EXPECT_NEAR(client->stats().swept_area, swept, 1e-4 * swept);
    const double reference = cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {}));
    ASSERT_GT(reference, 0.0);

    load(6);
    const CutResult end = stroke();
    EXPECT_EQ(end.triangles + end.deferred, 20u);
    EXPECT_GT(end.deferred, 0u) << "6 cells per tick should not hold the whole move";
    const int ticks = drain(200);
    EXPECT_GE(ticks, 2);
    EXPECT_LE(ticks, 200) << "the deferred quads were never cut";
    // The block sags a little between the ticks (the blade maps through it: 2e-5 of the swept
    // area, 0.1 % of the cut area here).
    EXPECT_NEAR(client->stats().swept_area, swept, 1e-4 * swept);
    const double area = cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {}));
    EXPECT_NEAR(area / reference, 1.0, 0.03);
}

TEST_P(CutBudget, TheTriangleBudgetSpreadsALongCutOverTicks) {
    // limits.cut_triangles_per_tick (default 16), no cell budget: a 40-triangle cut applies 16
    // at once and the rest over the next ticks, and cuts what the whole cut does at once.
    const std::vector<Triangle3> tris = long_incision(20);
    ASSERT_EQ(protocol::Limits {}.cut_triangles_per_tick, 16u);
    double reference = 0;
    {
        ServerConfig c = test_config(dir, true);
        c.limits.cut_triangles_per_tick = 0; // no limit
        RunningServer unlimited(c);
        Client other(context, unlimited.control());
        LoadSceneParams p;
        p.scene_json = scene(GetParam(), 0);
        other.ok<SceneResult>(p);
        const CutResult whole = other.ok<CutResult>(CutParams { tris });
        EXPECT_EQ(whole.deferred, 0u);
        other.ok<RunState>(StepParams { 1 });
        reference = cut_area(other.ok<SurfaceSnapshot>(GetSurfaceParams {}));
    }
    ASSERT_GT(reference, 0.0);
    load(0);
    EXPECT_EQ(client->ok<HelloResult>(HelloParams {}).limits.cut_triangles_per_tick, 16u);
    const CutResult first = client->ok<CutResult>(CutParams { tris });
    EXPECT_EQ(first.triangles, 16u);
    EXPECT_EQ(first.deferred, 24u);
    // The request used the coming tick's 16; that tick cuts one (at least one per call), the
    // next 16, the last 7.
    EXPECT_EQ(drain(200), 3);
    const double area = cut_area(client->ok<SurfaceSnapshot>(GetSurfaceParams {}));
    EXPECT_NEAR(area / reference, 1.0, 0.03);
}

TEST_P(CutBudget, ACutRequestIsAWholeSweepFinishedAfterItsLastTriangle) {
    // A `cut` is one sweep: face snapping cuts the faces it held back (pinched edges) once the
    // request's last triangle is cut, as at a stroke's end. Before, they waited for some scalpel
    // stroke to end: a stroke of one sample ended afterwards still cut more of the first cut
    // (the small block, 1 cm tets: 9 of the 12 cm2 here, completeness 0.75). Whole at once,
    // and spread over ticks by the budget (the finish comes after the carried triangles).
    for (const int budget : { 0, 6 }) {
        load(budget);
        const CutResult cut = client->ok<CutResult>(CutParams { long_incision(4) });
        EXPECT_EQ(cut.triangles + cut.deferred, 8u);
        EXPECT_LE(drain(200), 200);
        const Stats done = client->stats();
        ASSERT_GT(done.cut_area, 0.0);
        // 2 x the swept area within the face-conforming bound of docs/scenes.md.
        EXPECT_NEAR(done.cut_completeness, 1.0, 0.1) << "budget " << budget;
        client->notify(ScalpelParams { 9, { 0.0, 0.015, 0.03 }, { 0.0, 0.015, 0.025 } });
        client->ok<CutResult>(EndStrokeParams { 9 });
        client->ok<RunState>(StepParams { 1 });
        const Stats after = client->stats();
        EXPECT_EQ(after.cut_area, done.cut_area)
            << "budget " << budget << ": a later stroke's end cut more of the `cut`";
        EXPECT_EQ(after.topology_version, done.topology_version) << "budget " << budget;
    }
}

INSTANTIATE_TEST_SUITE_P(Cutters, CutBudget, ::testing::Values(false, true),
    [](const ::testing::TestParamInfo<bool>& param) {
        return param.param ? std::string("CellSplitting") : std::string("FaceSnapping");
    });

} // namespace
} // namespace polycut::server::testing
