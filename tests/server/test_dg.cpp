// Method "dg" behind the server (issue 13): an inline DG scene loads, steps, takes a grab and a
// cut through the protocol, and streams a surface whose vertices follow the stitched field
// (003 eq. 17), exactly as the other methods do; the client never needs to know the method.
#include "server_fixture.hpp"

namespace polycut::server::testing {
namespace {

using namespace protocol;

/// The small block of the other tests as DG p = 2 on 4 x 4 x 2 hexes.
const char* kDgScene = R"({
  "name": "small_dg",
  "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
               "cells": [4, 4, 2], "elements": "hex"},
  "method": "dg",
  "basis": {"degree": 2},
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000,
               "rayleigh_stiffness": 0.02},
  "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": true},
  "solver": {"type": "pcg", "preconditioner": "lagged_cholesky", "tolerance": 1e-6},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}],
  "loads": {"gravity": [0, 0, -9.81]}
})";

/// kDgScene on a hex-sliced sphere (003 sec. 10; 2.5 cm radius, 12 mm cubes) at p = 1,
/// fixed on its underside.
std::string hex_sliced_scene() {
    std::string s = kDgScene;
    auto swap
        = [&](const std::string& from_key, const std::string& to_key, const std::string& text) {
              const auto i = s.find(from_key), j = s.find(to_key, i);
              s.replace(i, j - i, text);
          };
    swap("\"geometry\"", "\"method\"",
        R"("geometry": {"type": "hex_slice", "surface": {"shape": "sphere", "radius": 0.025,
        "triangle_size": 0.004}, "cell_size": 0.012},
  )");
    swap("\"basis\"", "\"material\"", "\"basis\": {\"degree\": 1},\n  ");
    swap("\"fixed\"", "\"loads\"",
        R"("fixed": [{"box": {"min": [-0.03, -0.03, -0.03], "max": [0.03, 0.03, -0.018]}}],
  )");
    return s;
}

class DgServer : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };
};

float top_height(const SurfaceSnapshot& s) {
    float top = -1;
    for (std::size_t i = 2; i < s.positions.size(); i += 3)
        top = std::max(top, s.positions[i]);
    return top;
}

/// A two-triangle cut changes the topology, adds cells, and the simulation steps 5 more ticks
/// (cutting what the budget deferred).
void cut_and_step(Client& client, const std::vector<Triangle3>& blade, std::uint64_t cells_before,
    std::uint64_t tick_after) {
    const auto v0 = client.stats().topology_version;
    const auto cut = client.ok<CutResult>(CutParams { blade });
    // Both triangles now, or the second at the next tick when the first used the tick's cut
    // budget (docs/protocol.md "The cut budget": the hex-sliced cells are polyhedra of up to
    // ~60 corners, each changed one weighing (corners / 12)^2 tets).
    EXPECT_GE(cut.triangles, 1u);
    EXPECT_EQ(cut.triangles + cut.deferred, 2u);
    EXPECT_GT(cut.topology_version, v0);
    client.ok<RunState>(StepParams { 5 });
    const auto after = client.stats();
    EXPECT_GT(after.cell_count, cells_before);
    EXPECT_EQ(after.tick, tick_after);
}

} // namespace

TEST_F(DgServer, LoadsStepsGrabsAndCutsADgScene) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    LoadSceneParams load;
    load.scene_json = kDgScene;
    const auto loaded = client.ok<SceneResult>(load);
    EXPECT_EQ(loaded.cell_count, 4u * 4u * 2u);
    client.ok<RunState>(StepParams { 10 });
    const auto sagged = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
    EXPECT_EQ(sagged.header.tick, 10);
    // Under gravity the top sags a little below its rest height 0.02 m.
    EXPECT_LT(top_height(sagged), 0.02f);
    EXPECT_GT(top_height(sagged), 0.019f);
    // A grab on the top pulls it up.
    GrabParams g;
    g.point = { 0.0, 0.0, 0.02 };
    g.stiffness = 400.0;
    g.radius = 0.01;
    const auto grab = client.ok<Created>(g);
    client.ok<Ack>(MoveGrabParams { grab.id, { 0.0, 0.0, 0.03 } });
    client.ok<RunState>(StepParams { 20 });
    const auto pulled = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
    EXPECT_GT(top_height(pulled), 0.0205f);
    client.ok<Ack>(ReleaseParams { grab.id });
    // A cut changes the topology and the simulation steps on.
    cut_and_step(client, incision(0.003, -0.012, 0.012, 0.008), 4u * 4u * 2u, 35);
}

TEST_F(DgServer, LoadsStepsAndCutsAHexSlicedScene) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    LoadSceneParams load;
    load.scene_json = hex_sliced_scene();
    const auto loaded = client.ok<SceneResult>(load);
    EXPECT_GT(loaded.cell_count, 20u);
    client.ok<RunState>(StepParams { 10 });
    const auto sagged = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
    EXPECT_EQ(sagged.header.tick, 10);
    EXPECT_LT(top_height(sagged), 0.025f); // the top sags below the sphere's top
    EXPECT_GT(top_height(sagged), 0.02f);
    // A cut through the top of the sphere (z from 0.03 down to 0.01) splits cut cells.
    cut_and_step(client, incision(0.002, -0.02, 0.02, 0.01), loaded.cell_count, 15);
}

} // namespace polycut::server::testing
