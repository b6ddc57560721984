// Contact inside the time step: a free block dropped on a plane comes to rest on it under
// gravity, for penalty stiffnesses over five decades, at 60 Hz and at 1 kHz, with implicit
// Euler (the contact stiffness in the system matrix) and with semi-implicit Euler (per node).
// At rest the table carries the block's weight, and it sinks by about weight / (k area).
#include "polycut/contact/contact_field.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/surface/extract.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::integrate;

namespace {
constexpr double kSide = 0.04; // [m]
constexpr double kGravity = 9.81;

struct Block {
    mesh::Mesh mesh;
    std::unique_ptr<elasticity::ElasticModel> model;
    contact::ContactField field;
    double mass = 0;
};

/// A 4 cm hex block (2 x 2 x 2), 2 mm above the plane z = 0, sampled at its surface nodes.
std::unique_ptr<Block> block(double stiffness, double beta = 0.01, bool fix_xy = false) {
    auto b = std::make_unique<Block>();
    mesh::BoxGrid g;
    g.lo = Vec3(0, 0, 0.002);
    g.hi = g.lo + Vec3::Constant(kSide);
    g.cells = Eigen::Vector3i(2, 2, 2);
    b->mesh = mesh::hex_grid(g);
    elasticity::Material m;
    m.youngs_modulus = 2e4;
    m.poisson_ratio = 0.3;
    m.density = 1000;
    m.rayleigh_mass = 8.0;
    m.rayleigh_stiffness = beta;
    std::vector<std::uint8_t> fixed(3 * std::size_t(b->mesh.num_nodes()), 0);
    for (std::size_t k = 0; fix_xy && k < fixed.size(); ++k)
        fixed[k] = k % 3 != 2; // only z free: no rigid modes but the one contact holds
    b->model
        = std::make_unique<elasticity::ElasticModel>(b->mesh, m, basis::BasisOptions {}, fixed);
    b->mass = b->model->nodal_mass().sum();
    const surface::Topology topo = surface::extract_topology(b->mesh);
    b->field.set_samples(contact::node_samples(b->mesh.rest, topo.vertex_nodes, topo.triangles));
    contact::Body floor;
    floor.shape.kind = contact::Shape::Kind::Plane;
    floor.params.stiffness = stiffness;
    b->field.add_body(floor);
    return b;
}

struct Outcome {
    bool rolled_back = false;
    double lowest = 0; ///< lowest node z over the run [m]
    double final_bottom = 0; ///< mean z of the bottom nodes at the end [m]
    Vec3 reaction = Vec3::Zero(); ///< on the plane at the end [N]
    double speed = 0; ///< largest node speed at the end [m/s]
};

Outcome drop(double stiffness, IntegratorKind kind, double dt, double seconds) {
    // explicit elastic forces need no stiffness damping at 1 kHz (its limit is ~2e-4 s here)
    auto b = block(stiffness, kind == IntegratorKind::SemiImplicitEuler ? 0.0 : 0.01);
    IntegratorOptions o;
    o.kind = kind;
    o.dt = dt;
    o.gravity = Vec3(0, 0, -kGravity);
    o.solver.kind = LinearSolverKind::Cholmod;
    Integrator integ(*b->model, o);
    integ.set_penalty_field(&b->field);
    State s = integ.rest_state();
    Outcome out;
    out.lowest = 1;
    const int steps = int(std::lround(seconds / dt));
    for (int i = 0; i < steps; ++i) {
        const StepReport r = integ.step(s);
        out.rolled_back = out.rolled_back || r.rolled_back;
        out.lowest = std::min(out.lowest, s.x.col(2).minCoeff());
    }
    double bottom = 0;
    int count = 0;
    for (Index i = 0; i < s.x.rows(); ++i)
        if (b->mesh.rest[std::size_t(i)].z() < 0.002 + 1e-9) {
            bottom += s.x(i, 2);
            ++count;
        }
    out.final_bottom = bottom / count;
    out.reaction = b->field.reactions(s.x, s.v).begin()->second.force;
    out.speed = s.v.rowwise().norm().maxCoeff();
    return out;
}
} // namespace

class RestingBlock : public ::testing::TestWithParam<std::tuple<double, double, IntegratorKind>> {
};

TEST_P(RestingBlock, StableAndCarriesItsWeight) {
    const auto [stiffness, dt, kind] = GetParam();
    const double seconds = 2.0;
    const Outcome o = drop(stiffness, kind, dt, seconds);
    ASSERT_FALSE(o.rolled_back);
    auto b = block(stiffness);
    const double weight = b->mass * kGravity;
    // Uniform penetration d carries the weight when k d sum(a) = weight over the bottom
    // samples (whose areas include their thirds of the side triangles: node samples lump the
    // area around a node). The block's own compression makes it uneven: within 1.5x.
    const contact::Samples& samples = b->field.samples();
    double bottom_area = 0;
    for (std::size_t i = 0; i < samples.size(); ++i)
        if (b->mesh.rest[std::size_t(samples.nodes[i])].z() < 0.002 + 1e-9)
            bottom_area += samples.areas[i];
    const double sink = weight / (bottom_area * stiffness);
    // At rest: the plane carries the weight (1 %), the block has stopped, and it sits on
    // the plane, sunk by about `sink`, never through it by more than 2 cm.
    EXPECT_NEAR(o.reaction.z(), -weight, 0.01 * weight) << "k " << stiffness << " dt " << dt;
    EXPECT_LT(o.reaction.head<2>().norm(), 1e-6 * weight);
    EXPECT_LT(o.speed, 1e-3);
    EXPECT_GT(o.final_bottom, -1.5 * sink - 1e-9);
    EXPECT_LT(o.final_bottom, -sink / 1.5 + 1e-9);
    EXPECT_GT(o.lowest, -0.02);
}

INSTANTIATE_TEST_SUITE_P(StiffnessSweep, RestingBlock,
    ::testing::Combine(::testing::Values(1e5, 1e6, 1e7, 1e8, 1e9, 1e10),
        ::testing::Values(1.0 / 60.0, 1e-3), ::testing::Values(IntegratorKind::ImplicitEuler)));

TEST(RestingBlockSemiImplicit, PerNodePenaltyIsStableAtAHapticRate) {
    // Semi-implicit Euler keeps the elastic force explicit (its own limit), the contact
    // stiffness per node implicit: stiff penalties at 1 kHz hold the block on the plane.
    for (const double k : { 1e6, 1e8, 1e10 }) {
        const Outcome o = drop(k, IntegratorKind::SemiImplicitEuler, 1e-3, 1.5);
        ASSERT_FALSE(o.rolled_back) << k;
        auto b = block(k);
        const double weight = b->mass * kGravity;
        EXPECT_NEAR(o.reaction.z(), -weight, 0.02 * weight) << k;
        EXPECT_GT(o.lowest, -0.02) << k;
    }
}

TEST(RestingBlockStatic, NewtonFindsTheContactEquilibrium) {
    // Static corotated Newton, x and y held (the plane holds z): the penalty's stiffness in the
    // tangent and its energy in the line search take the block, hanging 2 mm above the plane
    // under gravity, to rest on it: the plane carries the weight to the solver's tolerance.
    for (const double k : { 1e5, 1e7, 1e9 }) {
        auto b = block(k, 0.0, true);
        IntegratorOptions o;
        o.kind = IntegratorKind::Static;
        o.gravity = Vec3(0, 0, -kGravity);
        o.solver.kind = LinearSolverKind::Cholmod;
        o.static_tolerance = 1e-10;
        Integrator integ(*b->model, o);
        integ.set_penalty_field(&b->field);
        State s = integ.rest_state();
        const StepReport r = integ.step(s);
        ASSERT_FALSE(r.rolled_back) << k;
        EXPECT_EQ(r.status, solve::SolveStatus::Ok) << k;
        const double weight = b->mass * kGravity;
        EXPECT_NEAR(b->field.reactions(s.x, s.v).begin()->second.force.z(), -weight, 1e-6 * weight)
            << k;
    }
}
