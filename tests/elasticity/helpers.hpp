// Shared helpers of the elasticity tests: grids, boundary loads, reduced linear solves.
#pragma once

#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/solve/cholmod_solver.hpp"

#include <functional>
#include <gtest/gtest.h>
#include <random>

namespace polycut::test {

inline MatX3 rest_matrix(const mesh::Mesh& m) {
    MatX3 X(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        X.row(i) = m.rest[std::size_t(i)].transpose();
    return X;
}

/// Consistent nodal loads of a uniform traction t [Pa] on the boundary faces whose nodes all
/// satisfy `on`: area / k per node of a k-gon (exact for triangles and for planar
/// parallelogram quads).
inline VecX traction_load(
    const mesh::Mesh& m, const Vec3& t, const std::function<bool(const Vec3&)>& on) {
    VecX f = VecX::Zero(3 * m.num_nodes());
    for (Index fid : m.boundary_faces()) {
        const auto& nodes = m.faces[std::size_t(fid)].nodes;
        bool all = true;
        for (Index i : nodes)
            all = all && on(m.rest[std::size_t(i)]);
        if (!all)
            continue;
        const double area = geometry::polygon_area(geometry::gather(m.rest, nodes));
        for (Index i : nodes)
            f.segment<3>(3 * i) += t * area / double(nodes.size());
    }
    return f;
}

/// Linear static solve: K u_free = f_free + f_int(x0) where x0 = X + u0 with the prescribed
/// displacements u0 on fixed DOFs (zero elsewhere). Returns world positions.
inline MatX3 solve_linear_static(
    elasticity::ElasticModel& model, const MatX3& x0, const VecX& f_ext) {
    solve::SparseMatrix K = model.make_matrix();
    VecX f_int;
    model.assemble(x0, elasticity::ForceMode::Linear, &K, &f_int);
    VecX rhs, fr;
    model.reduce(f_ext + f_int, rhs);
    solve::CholmodSolver chol;
    EXPECT_EQ(chol.factorize(K), solve::SolveStatus::Ok);
    VecX du;
    EXPECT_EQ(chol.solve(rhs, du), solve::SolveStatus::Ok);
    MatX3 x = x0;
    VecX xf = flat(x);
    VecX dfull = VecX::Zero(xf.size());
    model.expand(du, dfull);
    flat(x) += dfull;
    return x;
}

/// Box grid with interior nodes moved randomly by up to 0.25 of a cell.
inline mesh::Mesh distorted(bool hexes, const mesh::BoxGrid& g, unsigned seed) {
    mesh::Mesh m = hexes ? mesh::hex_grid(g) : mesh::tet_grid(g);
    std::mt19937 rng(seed);
    const Vec3 h = (g.hi - g.lo).cwiseQuotient(g.cells.cast<double>());
    std::uniform_real_distribution<double> jitter(-0.25, 0.25);
    for (int k = 1; k < g.cells.z(); ++k)
        for (int j = 1; j < g.cells.y(); ++j)
            for (int i = 1; i < g.cells.x(); ++i)
                m.rest[std::size_t(mesh::grid_node(g, i, j, k))]
                    += Vec3(jitter(rng) * h.x(), jitter(rng) * h.y(), jitter(rng) * h.z());
    return m;
}

inline std::vector<std::uint8_t> boundary_node_mask(const mesh::BoxGrid& g) {
    std::vector<std::uint8_t> mask(std::size_t((g.cells.array() + 1).prod()), 0);
    for (int k = 0; k <= g.cells.z(); ++k)
        for (int j = 0; j <= g.cells.y(); ++j)
            for (int i = 0; i <= g.cells.x(); ++i)
                if (i == 0 || j == 0 || k == 0 || i == g.cells.x() || j == g.cells.y()
                    || k == g.cells.z())
                    mask[std::size_t(mesh::grid_node(g, i, j, k))] = 1;
    return mask;
}

} // namespace polycut::test
