// The averaged nodal dilatation (basis.volumetric "nodal_average", decision 0050) through the
// facade: a tet block at nu = 0.49 under corotated backward Euler is softer than locked P1, is
// cut with face snapping and with cell splitting, steps on without rollback, and the model the
// cuts left behind (updated incrementally: cells, two-ring pattern, nodal patches) equals a
// model built afresh on the cut mesh.
#include "impl.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/sim/simulation.hpp"
#include "setup.hpp"

#include <gtest/gtest.h>

namespace polycut::sim {

struct SimulationTestPeer {
    static Simulation::Impl& impl(Simulation& s) { return *s.m_impl; }
};

namespace {
std::string block(const std::string& volumetric, const std::string& cut) {
    return R"({"name": "nodal_block",
      "geometry": {"type": "box", "origin": [-0.05, -0.05, 0], "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4], "elements": "tet"},
      "method": "tet",
      "basis": {"volumetric": ")"
        + volumetric + R"("},
      "cutting": {"method": ")"
        + cut + R"("},
      "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.49, "density": 1000, "rayleigh_stiffness": 0.02},
      "integrator": {"type": "implicit_euler", "dt": 0.01, "corotated": true},
      "solver": {"type": "cholmod"},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}}],
      "loads": {"gravity": [0, 0, -9.81]},
      "probes": [{"name": "tip", "point": [0.05, 0, 0.1]}]})";
}

/// Max |a - b| over max |b|.
double relative(const MatX& a, const MatX& b) {
    return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

class NodalCut : public ::testing::TestWithParam<const char*> { };
} // namespace

TEST_P(NodalCut, SofterThanP1CutStepsAndMatchesAFreshModel) {
    // The nodes of the mid plane x = 0 are fixed: both halves bend down under gravity (short
    // halves: shear matters as much as bending; measured 1.12x the P1 sag after 0.3 s).
    Simulation p1(scene::parse_scene(block("full", GetParam())));
    Simulation avg(scene::parse_scene(block("nodal_average", GetParam())));
    for (int i = 0; i < 30; ++i) {
        EXPECT_FALSE(p1.step().rolled_back);
        EXPECT_FALSE(avg.step().rolled_back);
    }
    const double sag_p1 = -p1.probe_displacement("tip").z();
    const double sag_avg = -avg.probe_displacement("tip").z();
    EXPECT_GT(sag_p1, 0);
    EXPECT_GT(sag_avg, 1.1 * sag_p1) << "P1 " << sag_p1 << " nodal " << sag_avg;
    // A cut through the hanging half, off the grid planes.
    const std::vector<std::array<Vec3, 3>> sweep {
        { Vec3(0.0137, -0.08, 0.13), Vec3(0.0137, -0.08, 0.04), Vec3(0.0137, 0.08, 0.13) },
        { Vec3(0.0137, -0.08, 0.04), Vec3(0.0137, 0.08, 0.04), Vec3(0.0137, 0.08, 0.13) }
    };
    const CutSummary c = avg.cut(sweep);
    EXPECT_TRUE(c.topology_changed);
    for (int i = 0; i < 30; ++i) {
        const StepReport r = avg.step();
        EXPECT_FALSE(r.rolled_back) << (r.warnings.empty() ? "" : r.warnings.front());
        EXPECT_FALSE(r.cut_undone);
    }
    for (const Vec3& x : avg.positions())
        ASSERT_TRUE(x.allFinite());
    EXPECT_TRUE(avg.mesh_stats().surface_closed);
    // The incrementally updated model against a fresh one on the same mesh and fixed DOFs.
    auto& impl = SimulationTestPeer::impl(avg);
    elasticity::ElasticModel& model = *impl.model;
    elasticity::ElasticModel fresh(
        impl.mesh, elasticity_material(impl.scene), basis_options(impl.scene), model.fixed_dofs());
    MatX3 x(impl.mesh.num_nodes(), 3);
    const auto positions = avg.positions();
    ASSERT_EQ(positions.size(), std::size_t(x.rows()));
    for (Index i = 0; i < x.rows(); ++i)
        x.row(i) = positions[std::size_t(i)].transpose();
    for (const auto mode : { elasticity::ForceMode::Linear, elasticity::ForceMode::Corotated }) {
        solve::SparseMatrix Ka = model.make_matrix(), Kb = fresh.make_matrix();
        VecX fa, fb;
        model.assemble(x, mode, &Ka, &fa);
        fresh.assemble(x, mode, &Kb, &fb);
        ASSERT_EQ(Ka.nonZeros(), Kb.nonZeros());
        // Linear: the same sums in the same order up to the cells' order; corotated: the warm
        // started rotations agree to the polar iteration's tolerance.
        const double tol = mode == elasticity::ForceMode::Linear ? 1e-12 : 1e-8;
        EXPECT_LE(relative(MatX(Ka), MatX(Kb)), tol);
        EXPECT_LE(relative(fa, fb), tol);
    }
}

INSTANTIATE_TEST_SUITE_P(SnapAndSplit, NodalCut, ::testing::Values("snap", "split"));

} // namespace polycut::sim
