// What the trade study (issue 17) needs from the facade: displacements sampled at rest points,
// model sizes, pressure loads (closed surface: no net force or moment), single-node 3-2-1
// supports, hexahedra given by their corners, and the Lame hollow sphere.
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {
sim::Simulation make(const std::string& text) {
    return sim::Simulation(scene::parse_scene(text));
}

const char* kBlock = R"({"name": "block",
  "geometry": {"type": "box", "size": [0.04, 0.04, 0.02], "cells": [4, 4, 2], "elements": "tet"},
  "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000},
  "integrator": {"type": "static", "corotated": false},
  "solver": {"type": "cholmod"},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
  "loads": {"gravity": [0, 0, -9.81]},
  "probes": [{"name": "top", "point": [0.02, 0.02, 0.02]}]})";
} // namespace

TEST(StudySupport, SamplesMatchProbesAndNodesAndFlagPointsOutside) {
    sim::Simulation s = make(kBlock);
    s.step();
    const std::vector<Vec3> pts { Vec3(0.02, 0.02, 0.02), Vec3(0.013, 0.007, 0.011),
        Vec3(0.01, 0.01, 0.005), Vec3(0.5, 0, 0) };
    std::vector<Vec3> u;
    std::vector<std::uint8_t> inside;
    s.sample_displacements(pts, u, inside);
    ASSERT_EQ(u.size(), 4u);
    EXPECT_EQ(inside, (std::vector<std::uint8_t> { 1, 1, 1, 0 }));
    EXPECT_LT((u[0] - s.probe_displacement("top")).norm(), 1e-15);
    EXPECT_GT(u[1].norm(), 0);
    EXPECT_LT(u[2].norm(), u[0].norm()); // lower in the sagging block, less displacement
    EXPECT_EQ(u[3], Vec3::Zero());
    const sim::ModelStats st = s.model_stats();
    EXPECT_EQ(st.tets, 4 * 4 * 2 * 6);
    EXPECT_EQ(st.hexes + st.polyhedra, 0);
    EXPECT_EQ(st.dofs, 3 * 5 * 5 * 3);
    EXPECT_EQ(st.free_dofs, 3 * 5 * 5 * 2); // the base layer is fixed
    EXPECT_GT(st.nonzeros, st.free_dofs);
}

TEST(StudySupport, CornersMapTheGridAndPressureOnAClosedSurfaceIsBalanced) {
    // Cook's trapezoid, 4 x 4 hexes: volume = trapezoid area x thickness = (44 + 16) / 2 x 48.
    const std::string cook = R"({"name": "cook",
      "geometry": {"type": "box", "corners": [[0,0,0],[48,44,0],[48,60,0],[0,44,0],[0,0,1],[48,44,1],[48,60,1],[0,44,1]],
                   "cells": [4, 4, 1], "elements": "hex"},
      "method": "hex",
      "material": {"youngs_modulus": 70, "poisson_ratio": 0.3},
      "integrator": {"type": "static", "corotated": false},
      "solver": {"type": "cholmod"},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}}],
      "probes": [{"name": "c", "point": [48, 60, 0]}]})";
    sim::Simulation c = make(cook);
    EXPECT_NEAR(c.mesh_stats().rest_volume, 0.5 * (44 + 16) * 48, 1e-9);
    EXPECT_EQ(c.model_stats().hexes, 16);

    // A free cube under pressure on its whole skin, held by 3-2-1 supports at three corner
    // nodes: a balanced load, so the cube shrinks uniformly, u = -p (1 - 2 nu) / E x about
    // the fully fixed corner (exact for P1: a linear field), with no reaction anywhere.
    const std::string cube = R"({"name": "squeeze",
      "geometry": {"type": "box", "size": [0.1, 0.1, 0.1], "cells": [3, 3, 3], "elements": "tet"},
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3},
      "integrator": {"type": "static", "corotated": false},
      "solver": {"type": "cholmod"},
      "fixed": [{"node": [0, 0, 0]}, {"node": [0.1, 0, 0], "components": "yz"},
                {"node": [0, 0.1, 0], "components": "z"}],
      "loads": {"pressure": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}, "pressure": 100}]},
      "probes": [{"name": "far", "point": [0.1, 0.1, 0.1]}]})";
    sim::Simulation s = make(cube);
    const sim::StepReport r = s.step();
    EXPECT_TRUE(r.warnings.empty());
    const double strain = -100 * (1 - 2 * 0.3) / 1e4;
    const Vec3 u = s.probe_displacement("far");
    EXPECT_NEAR(u.x(), strain * 0.1, 1e-9 * std::abs(strain));
    EXPECT_NEAR(u.y(), strain * 0.1, 1e-9 * std::abs(strain));
    EXPECT_NEAR(u.z(), strain * 0.1, 1e-9 * std::abs(strain));
}

TEST(StudySupport, HollowSphereMeshesBothSurfaces) {
    const std::string text = R"({"name": "shell",
      "geometry": {"type": "implicit", "shape": "hollow_sphere", "radius": 0.04, "inner_radius": 0.02,
                   "cell_size": 0.008},
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3},
      "integrator": {"type": "static", "corotated": false},
      "solver": {"type": "cholmod"},
      "fixed": [{"node": [0.02, 0, 0]}, {"node": [-0.02, 0, 0], "components": "yz"},
                {"node": [0, 0.02, 0], "components": "z"}],
      "loads": {"pressure": [{"box": {"min": [-0.021, -0.021, -0.021], "max": [0.021, 0.021, 0.021]}, "pressure": 100}]}})";
    sim::Simulation s = make(text);
    const sim::MeshStats m = s.mesh_stats();
    const double exact = 4.0 / 3.0 * 3.14159265358979 * (0.04 * 0.04 * 0.04 - 0.02 * 0.02 * 0.02);
    EXPECT_NEAR(m.rest_volume, exact, 0.03 * exact); // polyhedral approximation of both spheres
    EXPECT_EQ(m.components, 1);
    EXPECT_TRUE(m.surface_closed);
    // No node of the mesh inside the cavity.
    for (const Vec3& X : s.positions())
        EXPECT_GT(X.norm(), 0.019);
}
