// Test and benchmark matrices with the sparsity of tet-mesh elasticity: nodes on an
// nx x ny x nz grid, every node coupled to its 26 neighbours (27-point stencil) by a 3x3 block,
// three DOFs per node (node-major: DOF 3 i + c).
#pragma once

#include "polycut/solve/sparse.hpp"

#include <Eigen/Core>
#include <random>
#include <vector>

namespace polycut::solve::testing {

/// Node coupling: all 26 neighbours (Q1 hexes) or the 14 of a Kuhn-6 tet split along the main
/// diagonal (P1 tets, as in the bench_box scenes).
enum class Stencil { Hex27, Kuhn15 };

/// True if the offset (di, dj, dk) joins two nodes of a common Kuhn tet: all non-zero
/// components have the same sign.
inline bool kuhn_neighbour(int di, int dj, int dk) {
    const bool any_positive = di > 0 || dj > 0 || dk > 0;
    const bool any_negative = di < 0 || dj < 0 || dk < 0;
    return !(any_positive && any_negative);
}

/// Vector Laplacian-like stiffness: each neighbour pair (i, j) with unit direction d adds the
/// spring block B = k (0.5 I + d d^T), k uniform in [0.5, 1.5) from `seed`, to K_ii and K_jj and
/// -B to K_ij and K_ji. K is symmetric positive semi-definite with exactly the three rigid
/// translations as null space; `shift` I is added, so lambda_min(K) = shift.
inline SparseMatrix grid_matrix(
    int nx, int ny, int nz, double shift, unsigned seed = 1, Stencil stencil = Stencil::Hex27) {
    const auto node = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
    const int nodes = nx * ny * nz;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> stiffness(0.5, 1.5);
    std::vector<Eigen::Triplet<double, int>> triplets;
    triplets.reserve(static_cast<size_t>(nodes) * 27 * 9 + 3 * static_cast<size_t>(nodes));
    const auto add_block = [&](int a, int b, const Eigen::Matrix3d& block) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                triplets.emplace_back(3 * a + r, 3 * b + c, block(r, c));
    };
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (int dk = -1; dk <= 1; ++dk)
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            const int i2 = i + di, j2 = j + dj, k2 = k + dk;
                            if (i2 < 0 || j2 < 0 || k2 < 0 || i2 >= nx || j2 >= ny || k2 >= nz)
                                continue;
                            const int a = node(i, j, k), b = node(i2, j2, k2);
                            if (b <= a)
                                continue; // each pair once
                            if (stencil == Stencil::Kuhn15 && !kuhn_neighbour(di, dj, dk))
                                continue;
                            const Eigen::Vector3d d = Eigen::Vector3d(di, dj, dk).normalized();
                            const Eigen::Matrix3d block = stiffness(rng)
                                * (0.5 * Eigen::Matrix3d::Identity() + d * d.transpose());
                            add_block(a, a, block);
                            add_block(b, b, block);
                            add_block(a, b, -block);
                            add_block(b, a, -block);
                        }
    for (int i = 0; i < 3 * nodes; ++i)
        triplets.emplace_back(i, i, shift);
    SparseMatrix K(3 * nodes, 3 * nodes);
    K.setFromTriplets(triplets.begin(), triplets.end());
    K.makeCompressed();
    return K;
}

/// Gershgorin upper bound of the largest eigenvalue of a symmetric matrix.
inline double gershgorin_bound(const SparseMatrix& A) {
    double bound = 0;
    for (int j = 0; j < A.outerSize(); ++j) {
        double sum = 0;
        for (SparseMatrix::InnerIterator it(A, j); it; ++it)
            sum += std::abs(it.value());
        bound = std::max(bound, sum);
    }
    return bound;
}

/// Reproducible random vector with entries in [-1, 1].
inline Vector random_vector(long n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vector v(n);
    for (long i = 0; i < n; ++i)
        v[i] = u(rng);
    return v;
}

} // namespace polycut::solve::testing
