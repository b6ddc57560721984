// Test fixture shared by the AMG tests: the stiffness of a Kuhn tet box and PCG options with the
// AMG preconditioner.
#pragma once

#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/solve/pcg.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace polycut::solve::testing {

/// Stiffness (and lumped mass per free DOF) of an n^3-block Kuhn box of side 0.1 m, x = 0 fixed.
struct BoxSystem {
    SparseMatrix K;
    Vector mass;
    Vector coordinates; ///< rest coordinate of each free DOF's node along its component [m]
};

inline BoxSystem box_system(int n, double nu = 0.45) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    const mesh::Mesh m = mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
    std::vector<std::uint8_t> fixed(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        fixed[std::size_t(i)] = std::abs(m.rest[std::size_t(i)].x()) < 1e-9;
    elasticity::Material material;
    material.youngs_modulus = 1e4;
    material.poisson_ratio = nu;
    material.density = 1000;
    elasticity::ElasticModel model(
        m, material, basis::BasisOptions {}, elasticity::fix_nodes(fixed));
    BoxSystem s;
    s.K = model.make_matrix();
    VecX f;
    MatX3 x(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        x.row(i) = m.rest[std::size_t(i)].transpose();
    model.assemble(x, elasticity::ForceMode::Linear, &s.K, &f);
    s.mass = model.reduced_mass();
    model.reduce(VecX(flat(x)), s.coordinates);
    return s;
}

inline PcgOptions amg_options(double tol) {
    PcgOptions o;
    o.preconditioner = Preconditioner::Amg;
    o.relative_tolerance = tol;
    o.max_iterations = 500;
    return o;
}

} // namespace polycut::solve::testing
