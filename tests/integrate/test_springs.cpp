// Implicit penalty springs (issue 14 item 2): a grab spring's stiffness enters the system, so
// any stiffness in the documented range (0, 1e9] N/m is stable at 60 Hz and at 1 kHz, and the
// motion settles at the static equilibrium with the same spring.
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::elasticity;
using namespace polycut::integrate;

namespace {
struct Beam {
    std::unique_ptr<mesh::Mesh> mesh_ptr;
    std::unique_ptr<ElasticModel> model;
};

/// Beam [0, 0.4] x [0, 0.1] x [0, 0.1] of 4 x 1 x 1 hexes, fixed at x = 0.
Beam beam(const Material& mat) {
    Beam s;
    mesh::BoxGrid g;
    g.hi = Vec3(0.4, 0.1, 0.1);
    g.cells = Eigen::Vector3i(4, 1, 1);
    s.mesh_ptr = std::make_unique<mesh::Mesh>(mesh::hex_grid(g));
    const mesh::Mesh& m = *s.mesh_ptr;
    std::vector<std::uint8_t> node_fix(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        node_fix[std::size_t(i)] = m.rest[std::size_t(i)].x() == 0.0;
    s.model = std::make_unique<ElasticModel>(m, mat, basis::BasisOptions {}, fix_nodes(node_fix));
    return s;
}

Material tissue() {
    Material m;
    m.youngs_modulus = 1e5;
    m.poisson_ratio = 0.3;
    m.density = 1000;
    m.rayleigh_mass = 8.0;
    m.rayleigh_stiffness = 0.01;
    return m;
}

/// The tip corner (0.4, 0.1, 0.1) pulled 2 cm up by a spring of stiffness k.
Index tip(const mesh::Mesh& m) {
    for (Index i = 0; i < m.num_nodes(); ++i)
        if ((m.rest[std::size_t(i)] - Vec3(0.4, 0.1, 0.1)).norm() < 1e-12)
            return i;
    return kNone;
}
NodeSpring pull(const mesh::Mesh& m, double k) {
    return { tip(m), Vec3(0.4, 0.1, 0.12), k };
}

const double kStiffnesses[] = { 1e1, 1e3, 1e5, 1e7, 1e9 };
} // namespace

TEST(Springs, StaticEquilibriumBalancesElasticAndSpringForces) {
    // Linear statics: one solve of (K + K_s) u = f_s(X). Checked against the forces themselves:
    // the elastic force the model assembles at the solution balances the spring's on every free
    // DOF, and the stiffer the spring, the closer the node to its anchor (|x - a| = |f_el| / k).
    Beam s = beam(tissue());
    const mesh::Mesh& m = *s.mesh_ptr;
    double gap_before = 1.0;
    for (const double k : kStiffnesses) {
        IntegratorOptions o;
        o.kind = IntegratorKind::Static;
        o.static_mode = StaticMode::Linear;
        o.solver.kind = LinearSolverKind::Cholmod;
        Integrator integ(*s.model, o);
        const NodeSpring spring = pull(m, k);
        integ.set_springs({ spring });
        State st = integ.rest_state();
        const StepReport r = integ.step(st);
        ASSERT_FALSE(r.rolled_back) << "k " << k;
        VecX f_full, f_r;
        s.model->assemble(st.x, ForceMode::Linear, nullptr, &f_full);
        s.model->reduce(f_full, f_r);
        VecX f_s = VecX::Zero(f_r.size());
        add_spring_forces({ spring }, st.x, s.model->dof_map(), f_s);
        EXPECT_LT((f_r + f_s).norm(), 1e-8 * std::max(f_s.norm(), 1e-12)) << "k " << k;
        const double gap = (st.x.row(spring.node).transpose() - spring.anchor).norm();
        EXPECT_LT(gap, gap_before) << "k " << k;
        EXPECT_NEAR(gap, f_s.norm() / k, 1e-9 * gap + 1e-15) << "k " << k;
        gap_before = gap;
    }
    EXPECT_LT(gap_before, 1e-6 * 0.02); // 1e9 N/m: the node sits on its anchor
}

TEST(Springs, ImplicitEulerIsStableAndSettlesForAnyStiffness) {
    // 1e1..1e9 N/m at 60 Hz and 1 kHz: never rolled back, the distance to the equilibrium never
    // grows past its start (no overshoot growth), and the motion settles at the static solution
    // with the same spring (corotated Newton, itself checked above in the linear case).
    Beam s = beam(tissue());
    const mesh::Mesh& m = *s.mesh_ptr;
    const Index n = tip(m);
    std::vector<State> refs;
    for (const double k : kStiffnesses) {
        IntegratorOptions o;
        o.kind = IntegratorKind::Static;
        o.static_tolerance = 1e-11;
        o.solver.kind = LinearSolverKind::Cholmod;
        Integrator stat(*s.model, o);
        stat.set_springs({ pull(m, k) });
        refs.push_back(stat.rest_state());
        const StepReport sr = stat.step(refs.back());
        ASSERT_FALSE(sr.rolled_back);
        ASSERT_TRUE(sr.warnings.empty()) << "k " << k << ": " << sr.warnings[0];
    }
    for (const double dt : { 1.0 / 60.0, 1e-3 }) {
        for (std::size_t j = 0; j < refs.size(); ++j) {
            const double k = kStiffnesses[j];
            const State& ref = refs[j];
            IntegratorOptions o;
            o.kind = IntegratorKind::ImplicitEuler;
            o.dt = dt;
            o.solver.kind = dt < 0.01 ? LinearSolverKind::PcgJacobi : LinearSolverKind::Cholmod;
            o.solver.relative_tolerance = 1e-12;
            Integrator dyn(*s.model, o);
            dyn.set_springs({ pull(m, k) });
            State st = dyn.rest_state();
            const double start = (st.x.row(n) - ref.x.row(n)).norm();
            double worst = 0;
            const int steps = int(std::lround(4.0 / dt));
            for (int i = 0; i < steps; ++i) {
                const StepReport r = dyn.step(st);
                ASSERT_FALSE(r.rolled_back) << "k " << k << " dt " << dt << ": " << r.warnings[0];
                worst = std::max(worst, (st.x.row(n) - ref.x.row(n)).norm());
            }
            const double moved = (ref.x.row(n) - dyn.rest_state().x.row(n)).norm();
            EXPECT_GT(moved, 1e-5) << "k " << k; // even 10 N/m moves the tip measurably
            EXPECT_LE(worst, start + 1e-12) << "k " << k << " dt " << dt;
            // measured: 1e-8 (10 N/m) .. 3e-7 (1e9 N/m) of the tip's motion after 4 s
            EXPECT_LT((st.x - ref.x).rowwise().norm().maxCoeff(), 1e-5 * moved)
                << "k " << k << " dt " << dt;
        }
    }
}

TEST(Springs, SemiImplicitEulerHoldsAStiffSpringPerNode) {
    // Semi-implicit Euler stays explicit in the elastic forces (dt below their limit), but a
    // spring is implicit per node: 1e9 N/m does not blow up, and the node ends on its anchor.
    Beam s = beam(tissue());
    const mesh::Mesh& m = *s.mesh_ptr;
    IntegratorOptions o;
    o.kind = IntegratorKind::SemiImplicitEuler;
    o.dt = 1e-4;
    Integrator integ(*s.model, o);
    const NodeSpring spring = pull(m, 1e9);
    integ.set_springs({ spring });
    State st = integ.rest_state();
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        const StepReport r = integ.step(st);
        ASSERT_FALSE(r.rolled_back) << "step " << i << ": " << r.warnings[0];
        worst = std::max(worst, (st.x.row(spring.node).transpose() - spring.anchor).norm());
    }
    EXPECT_LE(worst, 0.02 + 1e-12); // never farther than the 2 cm it started from
    EXPECT_LT((st.x.row(spring.node).transpose() - spring.anchor).norm(), 1e-4 * 0.02);
}
