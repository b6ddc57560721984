// The mean-dilatation (B-bar) element through the facade (issue 17 item 5): it works with
// corotation and with cell splitting (cut cells become mean value polyhedra with their own mean
// dilatation), and it is softer than full integration where full integration locks.
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {
std::string block(const std::string& volumetric, double nu) {
    return R"({"name": "bbar_block",
      "geometry": {"type": "box", "origin": [-0.05, -0.05, 0], "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4], "elements": "hex"},
      "method": "mvc",
      "basis": {"volumetric": ")"
        + volumetric + R"("},
      "material": {"youngs_modulus": 3e4, "poisson_ratio": )"
        + std::to_string(nu) + R"(, "density": 1000, "rayleigh_stiffness": 0.02},
      "integrator": {"type": "implicit_euler", "dt": 0.01, "corotated": true},
      "solver": {"type": "cholmod"},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}}],
      "loads": {"gravity": [0, 0, -9.81]},
      "probes": [{"name": "tip", "point": [0.05, 0, 0.1]}]})";
}
} // namespace

TEST(MeanDilatation, CorotatedAndCutStepsWithoutRollbackAndIsSofterThanLockedQ1) {
    // The nodes of the block's mid plane x = 0 are fixed: its two halves bend down under
    // gravity like two short cantilevers, a bending the full-integration hexes lock on.
    sim::Simulation full(scene::parse_scene(block("full", 0.49)));
    sim::Simulation bbar(scene::parse_scene(block("mean_dilatation", 0.49)));
    for (int i = 0; i < 30; ++i) {
        EXPECT_FALSE(full.step().rolled_back);
        EXPECT_FALSE(bbar.step().rolled_back);
    }
    const double sag_full = -full.probe_displacement("tip").z();
    const double sag_bbar = -bbar.probe_displacement("tip").z();
    EXPECT_GT(sag_full, 0);
    EXPECT_GT(sag_bbar, 1.1 * sag_full) << "full " << sag_full << " bbar " << sag_bbar;
    // A cut through the hanging half: split cells become mvc polyhedra with the mean dilatation.
    const std::vector<std::array<Vec3, 3>> sweep {
        { Vec3(0.0125, -0.08, 0.13), Vec3(0.0125, -0.08, 0.04), Vec3(0.0125, 0.08, 0.13) },
        { Vec3(0.0125, -0.08, 0.04), Vec3(0.0125, 0.08, 0.04), Vec3(0.0125, 0.08, 0.13) }
    };
    const sim::CutSummary c = bbar.cut(sweep);
    EXPECT_GT(c.cells_split, 0);
    EXPECT_GT(bbar.model_stats().polyhedra, 0);
    for (int i = 0; i < 30; ++i) {
        const sim::StepReport r = bbar.step();
        EXPECT_FALSE(r.rolled_back) << (r.warnings.empty() ? "" : r.warnings.front());
        EXPECT_FALSE(r.cut_undone);
    }
    for (const Vec3& x : bbar.positions())
        ASSERT_TRUE(x.allFinite());
    EXPECT_TRUE(bbar.mesh_stats().surface_closed);
}
