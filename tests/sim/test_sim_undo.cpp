// The undo of a failed cut (Simulation::cut restores its snapshot when the cutter or the model
// update throws): a snapshot taken before a cut and restored after it gives back the same state,
// mesh and surface, and the simulation steps on as if the cut never happened.
#include "impl.hpp"
#include "polycut/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <gtest/gtest.h>

namespace polycut::sim {

struct SimulationTestPeer {
    static Simulation::Impl& impl(Simulation& s) { return *s.m_impl; }
};

namespace {
const char* kBlock = R"({"name": "undo_block",
  "geometry": {"type": "box", "origin": [-0.05, -0.05, 0], "size": [0.1, 0.1, 0.1], "cells": [3, 3, 3], "elements": "hex"},
  "method": "mvc",
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.3, "density": 1000, "rayleigh_stiffness": 0.02},
  "integrator": {"type": "implicit_euler", "dt": 0.01},
  "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-10},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
  "loads": {"gravity": [0, 0, -9.81]},
  "probes": [{"name": "top", "point": [0, 0, 0.1]}]})";
} // namespace

TEST(SimulationUndo, RestoringTheSnapshotUndoesACut) {
    Simulation a(scene::parse_scene(kBlock)), b(scene::parse_scene(kBlock));
    for (int i = 0; i < 3; ++i) {
        a.step();
        b.step();
    }
    auto& ia = SimulationTestPeer::impl(a);
    const auto snap = ia.take_snapshot();
    const Vec3 p(0.01, -0.2, -0.1), q(0.01, 0.2, -0.1), r(0.01, 0.2, 0.3), t(0.01, -0.2, 0.3);
    ASSERT_TRUE(a.cut({ { p, q, r }, { p, r, t } }).topology_changed);
    ASSERT_EQ(a.mesh_stats().components, 2);
    ia.restore(*snap);
    // Same mesh and state as the simulation that never cut, bit for bit; the same future up to the
    // solver tolerance (the rebuilt model restarts its rotation warm starts).
    EXPECT_EQ(a.mesh_stats().cells, b.mesh_stats().cells);
    EXPECT_EQ(a.mesh_stats().nodes, b.mesh_stats().nodes);
    EXPECT_EQ(a.mesh_stats().components, 1);
    EXPECT_EQ(a.state_hash(), b.state_hash());
    EXPECT_EQ(a.surface().triangles, b.surface().triangles);
    for (int i = 0; i < 3; ++i) {
        const StepReport ra = a.step(), rb = b.step();
        EXPECT_FALSE(ra.rolled_back);
        EXPECT_FALSE(rb.rolled_back);
    }
    double diff = 0;
    for (std::size_t i = 0; i < b.positions().size(); ++i) {
        diff = std::max(diff, (a.positions()[i] - b.positions()[i]).norm());
    }
    const double sag = std::abs(b.probe_displacement("top").z());
    EXPECT_GT(sag, 1e-4); // the block does sag under gravity
    EXPECT_LT(diff, 1e-8 * sag);
    // And it can be cut again afterwards.
    EXPECT_TRUE(a.cut({ { p, q, r }, { p, r, t } }).topology_changed);
    EXPECT_EQ(a.mesh_stats().components, 2);
}

/// Grabs the block's top corner with a 1e9 N/m spring and pulls it 1 m away: the (implicit)
/// spring drags the corner there in one step, stretching its cells far past the explosion guard.
void pull_hard(Simulation& a) {
    GrabSpec g;
    g.point = Vec3(0.05, 0.05, 0.1);
    g.stiffness = 1e9;
    const long id = a.grab(g);
    ASSERT_TRUE(a.move_grab(id, Vec3(1.0, 0.05, 0.1)));
}

TEST(SimulationUndo, AStepThatExplodesRightAfterACutUndoesTheCut) {
    // A grab spring of 1e9 N/m pulled 1 m away drags the corner 1 m in one step: the step after
    // the cut explodes (a cell stretches past IntegratorOptions::stretch_limit), is rolled back,
    // and takes the cut with it. Nothing exploded is ever in positions().
    Simulation a(scene::parse_scene(kBlock));
    a.step();
    const auto cells = a.mesh_stats().cells;
    const auto hash_before = a.state_hash();
    const std::vector<Vec3> before = a.positions();
    const Vec3 p(0.01, -0.2, -0.1), q(0.01, 0.2, -0.1), r(0.01, 0.2, 0.3), t(0.01, -0.2, 0.3);
    ASSERT_TRUE(a.cut({ { p, q, r }, { p, r, t } }).topology_changed);
    pull_hard(a);
    const StepReport report = a.step();
    EXPECT_TRUE(report.rolled_back);
    EXPECT_TRUE(report.cut_undone);
    ASSERT_FALSE(report.warnings.empty());
    EXPECT_EQ(a.mesh_stats().cells, cells);
    EXPECT_EQ(a.mesh_stats().components, 1);
    ASSERT_EQ(a.positions().size(), before.size());
    double moved = 0;
    for (std::size_t i = 0; i < before.size(); ++i)
        moved = std::max(moved, (a.positions()[i] - before[i]).norm());
    EXPECT_EQ(moved, 0.0); // the state before the cut, bit for bit
    EXPECT_EQ(a.state_hash(), hash_before);
    // The grab was made after the cut and went with it; the next step is sound.
    const StepReport next = a.step();
    EXPECT_FALSE(next.rolled_back);
    EXPECT_FALSE(next.cut_undone);
}

namespace {
const char* kTetBlock = R"({"name": "undo_tets",
  "geometry": {"type": "box", "origin": [-0.05, -0.05, 0], "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4]},
  "method": "mvc",
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.3, "density": 1000, "rayleigh_stiffness": 0.02},
  "integrator": {"type": "implicit_euler", "dt": 0.01, "threads": 2},
  "solver": {"type": "pcg", "preconditioner": "amg", "tolerance": 1e-10},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
  "loads": {"gravity": [0, 0, -9.81]},
  "probes": [{"name": "top", "point": [0, 0, 0.1]}]})";

long bases(const elasticity::ElasticModel& m) {
    const auto& b = m.bases_built();
    return b.p1 + b.q1 + b.polyhedral;
}
} // namespace

class SimulationUndoJournal : public ::testing::TestWithParam<const char*> { };

TEST_P(SimulationUndoJournal, AnUndoneCutPutsTheModelBackWithoutMakingACellAgain) {
    // Decision 0070: the step after a cut explodes, and the undo takes the model back from its
    // journal: the cells the cut replaced return and the appended ones go, with no basis made
    // again; the model is then the one of a simulation that never cut, to the bit: DOFs,
    // pattern, masses and the (linear) stiffness; and both step on alike.
    // The undo compares the pattern it made around the reverted cells with a full build.
    ::setenv("POLYCUT_CHECK_UNDO", "1", 1);
    Simulation a(scene::parse_scene(GetParam())), b(scene::parse_scene(GetParam()));
    a.step();
    b.step();
    auto& ia = SimulationTestPeer::impl(a);
    const auto& ib = SimulationTestPeer::impl(b);
    ASSERT_TRUE(ia.model && ib.model);
    // a second cut in the same tick: the undo goes back past both
    const Vec3 p(0.01, -0.2, -0.1), q(0.01, 0.2, -0.1), r(0.01, 0.2, 0.3), t(0.01, -0.2, 0.3);
    ASSERT_TRUE(a.cut({ { p, q, r }, { p, r, t } }).topology_changed);
    const Vec3 p2(-0.2, -0.012, -0.1), q2(0.2, -0.012, -0.1), r2(0.2, -0.012, 0.3),
        t2(-0.2, -0.012, 0.3);
    ASSERT_TRUE(a.cut({ { p2, q2, r2 }, { p2, r2, t2 } }).topology_changed);
    EXPECT_GE(a.mesh_stats().components, 3); // (4 when neither cut is deferred)
    EXPECT_EQ(ia.model->undo_marks(), 1u); // only the tick's first snapshot stays restorable
    const long made_by_cuts = bases(*ia.model);
    pull_hard(a);
    const StepReport report = a.step();
    ASSERT_TRUE(report.cut_undone);
    EXPECT_EQ(bases(*ia.model), made_by_cuts); // nothing made again (a rebuild makes every cell)
    EXPECT_EQ(ia.model->undo_marks(), 0u);
    EXPECT_EQ(a.mesh_stats().components, 1);
    const elasticity::ElasticModel &ma = *ia.model, &mb = *ib.model;
    ASSERT_EQ(ma.num_free_dofs(), mb.num_free_dofs());
    EXPECT_EQ(ma.dof_map(), mb.dof_map());
    EXPECT_EQ(ma.diagonal_slots(), mb.diagonal_slots());
    EXPECT_EQ(ma.row_mass(), mb.row_mass());
    elasticity::ElasticModel& wa = *ia.model;
    elasticity::ElasticModel& wb = *SimulationTestPeer::impl(b).model;
    SparseMatrix Ka = wa.make_matrix(), Kb = wb.make_matrix();
    VecX fa, fb;
    MatX3 x(Index(a.positions().size()), 3);
    for (Index i = 0; i < x.rows(); ++i)
        x.row(i) = a.positions()[std::size_t(i)].transpose();
    wa.assemble(x, elasticity::ForceMode::Linear, &Ka, &fa);
    wb.assemble(x, elasticity::ForceMode::Linear, &Kb, &fb);
    ASSERT_EQ(Ka.nonZeros(), Kb.nonZeros());
    for (Index k = 0; k <= Ka.outerSize(); ++k)
        ASSERT_EQ(Ka.outerIndexPtr()[k], Kb.outerIndexPtr()[k]);
    for (Index k = 0; k < Ka.nonZeros(); ++k) {
        ASSERT_EQ(Ka.innerIndexPtr()[k], Kb.innerIndexPtr()[k]);
        ASSERT_EQ(Ka.valuePtr()[k], Kb.valuePtr()[k]);
    }
    EXPECT_EQ(fa, fb);
    EXPECT_EQ(a.state_hash(), b.state_hash());
    for (int i = 0; i < 3; ++i) {
        EXPECT_FALSE(a.step().rolled_back);
        EXPECT_FALSE(b.step().rolled_back);
    }
    double diff = 0;
    for (std::size_t i = 0; i < b.positions().size(); ++i)
        diff = std::max(diff, (a.positions()[i] - b.positions()[i]).norm());
    const double sag = std::abs(b.probe_displacement("top").z());
    EXPECT_GT(sag, 1e-4);
    EXPECT_LT(diff, 1e-8 * sag); // the solves' tolerance (1e-10) and the restarted rotations
    // and it cuts again as the first time
    EXPECT_TRUE(a.cut({ { p, q, r }, { p, r, t } }).topology_changed);
    EXPECT_EQ(a.mesh_stats().components, 2);
    EXPECT_FALSE(a.step().rolled_back);
    ::unsetenv("POLYCUT_CHECK_UNDO");
}

INSTANTIATE_TEST_SUITE_P(
    HexAndTetBlocks, SimulationUndoJournal, ::testing::Values(kBlock, kTetBlock));

TEST(SimulationUndo, AnExplodingStepWithoutACutIsRolledBackAndReported) {
    Simulation a(scene::parse_scene(kBlock));
    a.step();
    const std::vector<Vec3> before = a.positions();
    pull_hard(a);
    const StepReport report = a.step();
    EXPECT_TRUE(report.rolled_back);
    EXPECT_FALSE(report.cut_undone);
    for (std::size_t i = 0; i < before.size(); ++i)
        ASSERT_EQ(a.positions()[i], before[i]);
}

} // namespace polycut::sim
