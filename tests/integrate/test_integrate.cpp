// Integrators: damped implicit Euler settles at the static solution, energy never grows without
// input, stability over a sweep of dt / E / nu, rollback on NaN, static modes agree, solvers
// agree.
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <tuple>

using namespace polycut;
using namespace polycut::elasticity;
using namespace polycut::integrate;

namespace {
/// The model points at the mesh, so both live on the heap and survive moves.
struct Beam {
    std::unique_ptr<mesh::Mesh> mesh_ptr;
    std::unique_ptr<ElasticModel> model;
    const mesh::Mesh& mesh() const { return *mesh_ptr; }
};

/// Beam [0, 0.4] x [0, 0.1] x [0, 0.1] fixed at x = 0.
Beam beam(bool hexes, const Material& mat, Eigen::Vector3i cells = { 8, 2, 2 },
    const basis::BasisOptions& basis = {}) {
    Beam s;
    mesh::BoxGrid g;
    g.hi = Vec3(0.4, 0.1, 0.1);
    g.cells = cells;
    s.mesh_ptr = std::make_unique<mesh::Mesh>(hexes ? mesh::hex_grid(g) : mesh::tet_grid(g));
    const mesh::Mesh& m = *s.mesh_ptr;
    std::vector<std::uint8_t> node_fix(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        node_fix[std::size_t(i)] = m.rest[std::size_t(i)].x() == 0.0;
    s.model = std::make_unique<ElasticModel>(m, mat, basis, fix_nodes(node_fix));
    return s;
}

Material soft() {
    Material m;
    m.youngs_modulus = 1e6;
    m.poisson_ratio = 0.3;
    m.density = 1000;
    m.rayleigh_mass = 5.0;
    m.rayleigh_stiffness = 0.01;
    return m;
}

double max_diff(const MatX3& a, const MatX3& b) {
    return (a - b).rowwise().norm().maxCoeff();
}
} // namespace

TEST(Static, CorotatedModesAgreeAndLinearMatchesForSmallLoads) {
    Beam s = beam(false, soft());
    IntegratorOptions o;
    o.kind = IntegratorKind::Static;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = LinearSolverKind::Cholmod;
    o.static_tolerance = 1e-10;
    MatX3 results[3];
    int k = 0;
    for (StaticMode mode :
        { StaticMode::Linear, StaticMode::CorotatedFixedPoint, StaticMode::CorotatedNewton }) {
        o.static_mode = mode;
        Integrator integ(*s.model, o);
        State st = integ.rest_state();
        const StepReport r = integ.step(st);
        EXPECT_FALSE(r.rolled_back);
        EXPECT_TRUE(r.warnings.empty()) << (r.warnings.empty() ? "" : r.warnings[0]);
        results[k++] = st.x;
    }
    const MatX3 X = Integrator(*s.model, o).rest_state().x;
    const double sag = max_diff(results[0], X);
    EXPECT_GT(sag, 1e-2); // gravity sag of 3.4 cm (8 % of the length)
    // The two corotated iterations reach the same equilibrium.
    EXPECT_LT(max_diff(results[1], results[2]), 1e-8 * sag);
    // Linear and corotated differ at second order in the rotation (sag / length ~ 8 %).
    EXPECT_LT(max_diff(results[0], results[1]), 0.05 * sag);
    EXPECT_GT(max_diff(results[0], results[1]), 1e-6 * sag);
}

TEST(ImplicitEuler, DampedSettlesAtStaticSolution) {
    for (bool hexes : { false, true }) {
        Beam s = beam(hexes, soft());
        IntegratorOptions o;
        o.gravity = Vec3(0, 0, -9.81);
        o.solver.kind = LinearSolverKind::PcgJacobi;
        o.solver.relative_tolerance = 1e-10;
        o.kind = IntegratorKind::Static;
        o.static_tolerance = 1e-11;
        o.solver.kind = LinearSolverKind::Cholmod;
        Integrator stat(*s.model, o);
        State ref = stat.rest_state();
        stat.step(ref);

        o.kind = IntegratorKind::ImplicitEuler;
        o.dt = 0.02;
        o.solver.kind = LinearSolverKind::PcgJacobi;
        Integrator dyn(*s.model, o);
        State st = dyn.rest_state();
        for (int i = 0; i < 400; ++i) {
            const StepReport r = dyn.step(st);
            ASSERT_FALSE(r.rolled_back) << r.warnings[0];
        }
        const double sag = max_diff(ref.x, dyn.rest_state().x);
        EXPECT_LT(max_diff(st.x, ref.x), 1e-6 * sag) << (hexes ? "Q1" : "P1");
        EXPECT_LT(st.v.norm(), 1e-6 * sag);
    }
}

TEST(ImplicitEuler, EnergyNeverGrowsWithoutInput) {
    // Released from a stretched and bent state with no gravity and no forces, undamped and
    // damped: backward Euler is dissipative, so kinetic + elastic energy decreases every step.
    for (double beta : { 0.0, 0.01 }) {
        Material mat = soft();
        mat.rayleigh_mass = 0;
        mat.rayleigh_stiffness = beta;
        Beam s = beam(false, mat);
        IntegratorOptions o;
        o.dt = 0.005;
        o.solver.kind = LinearSolverKind::Cholmod;
        Integrator integ(*s.model, o);
        State st = integ.rest_state();
        for (Index i = 0; i < st.x.rows(); ++i) {
            const double x = st.x(i, 0);
            st.x(i, 0) += 0.05 * x;
            st.x(i, 2) += 0.5 * x * x;
        }
        double e = integ.energy(st);
        const double e0 = e;
        for (int i = 0; i < 200; ++i) {
            const StepReport r = integ.step(st);
            ASSERT_FALSE(r.rolled_back);
            const double en = integ.energy(st);
            EXPECT_LE(en, e * (1 + 1e-9)) << "step " << i << " beta " << beta;
            e = en;
        }
        EXPECT_LT(e, 0.9 * e0);
    }
}

namespace {
using StabilityParam = std::tuple<double, double, double>; // dt, E, nu
class Stability : public ::testing::TestWithParam<StabilityParam> { };
} // namespace

TEST_P(Stability, NoNaNAndBoundedDisplacement) {
    const auto [dt, E, nu] = GetParam();
    Material mat;
    mat.youngs_modulus = E;
    mat.poisson_ratio = nu;
    mat.density = 1000;
    mat.rayleigh_stiffness = 0.01;
    Beam s = beam(false, mat, { 4, 1, 1 });
    IntegratorOptions o;
    o.dt = dt;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = LinearSolverKind::Cholmod;
    // A 100 Pa beam hangs stretched far beyond the explosion guard's 10x: that is the model's
    // answer, not an explosion, so this sweep bounds the motion itself (below).
    o.stretch_limit = std::numeric_limits<double>::infinity();
    Integrator integ(*s.model, o);
    State st = integ.rest_state();
    const MatX3 X = st.x;
    for (int i = 0; i < 30; ++i) {
        const StepReport r = integ.step(st);
        ASSERT_FALSE(r.rolled_back) << "step " << i << ": " << r.warnings[0];
        ASSERT_TRUE(st.x.allFinite());
    }
    // Backward Euler free fall after n steps is g h^2 n (n + 1) / 2; elastic forces can only
    // hold nodes back, except for a swing about the clamp of at most twice the beam length.
    EXPECT_LT(max_diff(st.x, X), 9.81 * dt * dt * 30 * 31 / 2 + 2 * 0.4);
}

INSTANTIATE_TEST_SUITE_P(Sweep, Stability,
    ::testing::Combine(::testing::Values(1e-4, 1e-2, 0.1), ::testing::Values(1e2, 1e4, 1e8),
        ::testing::Values(0.0, 0.3, 0.49)));

TEST(Rollback, NaNForceIsRejectedAndStateUnchanged) {
    for (IntegratorKind kind : { IntegratorKind::ImplicitEuler, IntegratorKind::SemiImplicitEuler,
             IntegratorKind::Static }) {
        Beam s = beam(false, soft());
        IntegratorOptions o;
        o.kind = kind;
        o.dt = 1e-3;
        o.gravity = Vec3(0, 0, -9.81);
        Integrator integ(*s.model, o);
        State st = integ.rest_state();
        ASSERT_FALSE(integ.step(st).rolled_back);
        const State before = st;
        VecX f = VecX::Zero(3 * s.mesh().num_nodes());
        f(3 * (s.mesh().num_nodes() - 1) + 2) = std::nan("");
        integ.set_external_forces(f);
        const StepReport r = integ.step(st);
        EXPECT_TRUE(r.rolled_back);
        EXPECT_FALSE(r.warnings.empty());
        EXPECT_EQ(st.x, before.x);
        EXPECT_EQ(st.v, before.v);
        EXPECT_EQ(st.time, before.time);
        // Back to finite forces, the integrator steps again.
        integ.set_external_forces({});
        EXPECT_FALSE(integ.step(st).rolled_back);
    }
}

TEST(Solvers, CholmodAndPcgVariantsAgree) {
    Beam s = beam(false, soft());
    MatX3 results[5];
    int k = 0;
    for (LinearSolverKind kind :
        { LinearSolverKind::Cholmod, LinearSolverKind::PcgJacobi, LinearSolverKind::PcgBlockJacobi,
            LinearSolverKind::PcgLagged, LinearSolverKind::CgRelaxation }) {
        IntegratorOptions o;
        o.dt = 0.01;
        o.gravity = Vec3(0, 0, -9.81);
        o.solver.kind = kind;
        o.solver.relative_tolerance = 1e-10;
        Integrator integ(*s.model, o);
        State st = integ.rest_state();
        for (int i = 0; i < 10; ++i)
            ASSERT_FALSE(integ.step(st).rolled_back);
        results[k++] = st.x;
    }
    const double scale = max_diff(results[0], Integrator(*s.model, {}).rest_state().x);
    for (int i = 1; i < 5; ++i)
        EXPECT_LT(max_diff(results[i], results[0]), 1e-7 * scale) << "solver " << i;
}

TEST(Solvers, PreparedAmgHierarchyStepsBitForBitAsTheFirstStepWouldHave) {
    // Integrator::prepare sets up the AMG hierarchy of the first step's matrix ahead (a scene
    // load does it off the server's tick); the steps after it must be exactly those of an
    // integrator that set up inside its first step.
    IntegratorOptions o;
    o.dt = 1.0 / 60;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = LinearSolverKind::PcgAmg;
    o.solver.relative_tolerance = 1e-3;
    o.solver.amg.rigid_body_modes = true;
    // The step matrix straight from the kernels (Model::assemble_step), and the nodal
    // volumetric term, which has no such path (K assembled, then A formed from it).
    basis::BasisOptions nodal;
    nodal.volumetric = basis::VolumetricRule::NodalAverage;
    for (const basis::BasisOptions& b : { basis::BasisOptions {}, nodal }) {
        MatX3 x[2];
        for (int prepared = 0; prepared < 2; ++prepared) {
            // a model each: the corotated model keeps its rotations as the next polar start
            Beam s = beam(false, soft(), { 16, 4, 4 }, b);
            Integrator integ(*s.model, o);
            State st = integ.rest_state();
            if (prepared) {
                EXPECT_TRUE(integ.prepare(st));
            }
            for (int i = 0; i < 5; ++i)
                ASSERT_FALSE(integ.step(st).rolled_back);
            x[prepared] = st.x;
        }
        Beam s = beam(false, soft(), { 16, 4, 4 }, b);
        EXPECT_GT(max_diff(x[0], Integrator(*s.model, o).rest_state().x), 1e-4); // it moved [m]
        EXPECT_EQ(max_diff(x[0], x[1]), 0.0);
    }
    Beam s = beam(false, soft(), { 16, 4, 4 });
    // nothing to prepare for a solver that sets nothing up ahead
    o.solver.kind = LinearSolverKind::Cholmod;
    Integrator direct(*s.model, o);
    EXPECT_FALSE(direct.prepare(direct.rest_state()));
}

TEST(SemiImplicitEuler, SmallStepTracksImplicitEuler) {
    // Both first-order integrators converge to the same trajectory as dt -> 0.
    Material mat = soft();
    Beam s = beam(false, mat, { 4, 1, 1 });
    IntegratorOptions o;
    o.gravity = Vec3(0, 0, -9.81);
    o.dt = 2e-5;
    o.kind = IntegratorKind::SemiImplicitEuler;
    Integrator semi(*s.model, o);
    o.kind = IntegratorKind::ImplicitEuler;
    o.solver.kind = LinearSolverKind::Cholmod;
    Integrator impl(*s.model, o);
    State a = semi.rest_state(), b = impl.rest_state();
    for (int i = 0; i < 500; ++i) {
        ASSERT_FALSE(semi.step(a).rolled_back);
        ASSERT_FALSE(impl.step(b).rolled_back);
    }
    const double moved = max_diff(a.x, semi.rest_state().x);
    EXPECT_GT(moved, 1e-6);
    EXPECT_LT(max_diff(a.x, b.x), 0.02 * moved);
}

namespace {
/// Steps a beam 6 times, fixes the nodes at x = 0.05 as well (a new DOF numbering and sparsity
/// pattern, as after a cut), and steps 24 more times; returns the final positions.
MatX3 run_with_pattern_change(LinearSolverKind kind, Integrator::LaggedStatus* status = nullptr) {
    Beam s = beam(false, soft());
    IntegratorOptions o;
    o.dt = 0.01;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = kind;
    o.solver.relative_tolerance = 1e-10;
    o.solver.refactor_iterations = 1000; // only the pattern change triggers a new factor
    Integrator integ(*s.model, o);
    State st = integ.rest_state();
    for (int i = 0; i < 6; ++i)
        EXPECT_FALSE(integ.step(st).rolled_back);
    std::vector<std::uint8_t> node_fix(std::size_t(s.mesh().num_nodes()), 0);
    for (Index i = 0; i < s.mesh().num_nodes(); ++i)
        node_fix[std::size_t(i)] = s.mesh().rest[std::size_t(i)].x() <= 0.05 + 1e-12;
    s.model->set_fixed_dofs(fix_nodes(node_fix));
    for (int i = 0; i < 24; ++i)
        EXPECT_FALSE(integ.step(st).rolled_back);
    if (status)
        *status = integ.lagged_status();
    return st.x;
}
} // namespace

TEST(Solvers, LaggedFactorAfterPatternChangeIsBuiltOffTheStep) {
    // Issue 5 item 5: after a pattern change the new factor is analysed and factored on a worker
    // thread, block Jacobi carries the solves until a fixed hand-over, and the result agrees with
    // CHOLMOD and is the same bit for bit when run again (replays stay deterministic).
    Integrator::LaggedStatus status;
    const MatX3 lagged = run_with_pattern_change(LinearSolverKind::PcgLagged, &status);
    const MatX3 again = run_with_pattern_change(LinearSolverKind::PcgLagged);
    const MatX3 reference = run_with_pattern_change(LinearSolverKind::Cholmod);
    Beam s = beam(false, soft());
    const double scale = max_diff(reference, Integrator(*s.model, {}).rest_state().x);
    EXPECT_LT(max_diff(lagged, reference), 1e-7 * scale);
    EXPECT_EQ(max_diff(lagged, again), 0.0);
    EXPECT_EQ(status.foreground_factorizations, 1); // the first solve only
    EXPECT_EQ(status.background_factorizations, 1); // the pattern change
    const int free_dofs = 3 * 9 * 3 * 3 - 3 * 2 * 3 * 3; // (8+1)x3x3 nodes, 2 planes fixed
    EXPECT_EQ(status.bridged_solves, Integrator::handover_solves(free_dofs));
    EXPECT_FALSE(status.pending);
}

TEST(Solvers, HandoverGrowsWithTheSystem) {
    EXPECT_EQ(Integrator::handover_solves(100), 2);
    EXPECT_LT(Integrator::handover_solves(6000), Integrator::handover_solves(24000));
    EXPECT_GE(Integrator::handover_solves(24000), 20); // ~420 ms of factorization at 60 Hz
}

TEST(ImplicitEuler, LaggedStiffnessTracksTheEveryStepOneAndReachesTheSameRest) {
    // stiffness_every = 5 at a haptic step (1 ms): forces and rotations are new every step,
    // only the linearization lags, so after 200 steps of a swinging, sagging beam the positions
    // agree with assembling K_R every step to 1e-3 of the sag; and the damped beam still settles
    // at the static solution.
    Beam a = beam(false, soft()), b = beam(false, soft());
    IntegratorOptions o;
    o.gravity = Vec3(0, 0, -9.81);
    o.dt = 1e-3;
    o.solver.kind = LinearSolverKind::Cholmod;
    Integrator every(*a.model, o);
    o.stiffness_every = 5;
    Integrator lagged(*b.model, o);
    State sa = every.rest_state(), sb = lagged.rest_state();
    for (int i = 0; i < 200; ++i) {
        ASSERT_FALSE(every.step(sa).rolled_back);
        ASSERT_FALSE(lagged.step(sb).rolled_back);
    }
    const double sag = max_diff(sa.x, every.rest_state().x);
    EXPECT_GT(sag, 1e-6);
    EXPECT_LT(max_diff(sa.x, sb.x), 1e-3 * sag);

    o.dt = 0.02;
    Integrator settle(*b.model, o);
    State s = settle.rest_state();
    for (int i = 0; i < 400; ++i)
        ASSERT_FALSE(settle.step(s).rolled_back);
    o.kind = IntegratorKind::Static;
    o.static_tolerance = 1e-11;
    Integrator stat(*a.model, o);
    State ref = stat.rest_state();
    stat.step(ref);
    const double static_sag = max_diff(ref.x, stat.rest_state().x);
    EXPECT_LT(max_diff(s.x, ref.x), 1e-6 * static_sag);
}
