// Shared by the mesh-level basis tests (merged hex grids, octree meshes): the global stiffness
// of a mesh from its cells' Ke, and a solve with prescribed DOFs.
#pragma once

#include "polycut/basis/cell_basis.hpp"
#include "polycut/basis/cell_integration.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polyhedral_cells.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

namespace polycut::basis::testing {

/// Global stiffness (3N x 3N) of the mesh with Ke = sum_q w_q B^T C B per cell.
inline Eigen::SparseMatrix<double> assemble(
    const mesh::Mesh& m, const BasisOptions& options, const Eigen::Matrix<double, 6, 6>& C) {
    std::vector<Eigen::Triplet<double>> t;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const MatX K = stiffness(integrate_cell(m, c, options), C);
        const auto& nodes = m.cells[std::size_t(c)].nodes;
        for (std::size_t a = 0; a < nodes.size(); ++a)
            for (std::size_t b = 0; b < nodes.size(); ++b)
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        t.emplace_back(3 * nodes[a] + i, 3 * nodes[b] + j,
                            K(3 * Index(a) + i, 3 * Index(b) + j));
    }
    Eigen::SparseMatrix<double> K(3 * m.num_nodes(), 3 * m.num_nodes());
    K.setFromTriplets(t.begin(), t.end());
    return K;
}

/// Solves K u = f with the dofs in `fixed` prescribed to u_fixed.
inline VecX solve_with_fixed(
    const Eigen::SparseMatrix<double>& K, const VecX& f, const std::vector<bool>& fixed, VecX u) {
    const Index n = Index(K.rows());
    std::vector<Index> free_of(std::size_t(n), kNone);
    Index nf = 0;
    for (Index i = 0; i < n; ++i)
        if (!fixed[std::size_t(i)])
            free_of[std::size_t(i)] = nf++;
    std::vector<Eigen::Triplet<double>> t;
    VecX rhs = VecX::Zero(nf);
    for (int k = 0; k < K.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K, k); it; ++it) {
            const Index r = free_of[std::size_t(it.row())], c = free_of[std::size_t(it.col())];
            if (r == kNone)
                continue;
            if (c == kNone)
                rhs[r] -= it.value() * u[Index(it.col())];
            else
                t.emplace_back(r, c, it.value());
        }
    for (Index i = 0; i < n; ++i)
        if (free_of[std::size_t(i)] != kNone)
            rhs[free_of[std::size_t(i)]] += f[i];
    Eigen::SparseMatrix<double> Kf(nf, nf);
    Kf.setFromTriplets(t.begin(), t.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kf);
    const VecX x = ldlt.solve(rhs);
    for (Index i = 0; i < n; ++i)
        if (free_of[std::size_t(i)] != kNone)
            u[i] = x[free_of[std::size_t(i)]];
    return u;
}

} // namespace polycut::basis::testing
