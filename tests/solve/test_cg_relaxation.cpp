// Matrix-free CG relaxation with fixed DOFs (002 sec. 3.1) against a direct solve of the
// reduced system K_ff u_f = f_f - K_fc u_c.
#include "grid_matrix.hpp"
#include "polycut/solve/cg_relaxation.hpp"

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>
#include <vector>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

/// Direct solution with u fixed at u0 where fixed is true.
Vector reduced_solve(
    const SparseMatrix& K, const Vector& f, const std::vector<bool>& fixed, const Vector& u0) {
    const long n = K.rows();
    std::vector<int> free_index(static_cast<size_t>(n), -1);
    int m = 0;
    for (long i = 0; i < n; ++i)
        if (!fixed[static_cast<size_t>(i)])
            free_index[static_cast<size_t>(i)] = m++;
    std::vector<Eigen::Triplet<double, int>> triplets;
    Vector rhs(m);
    for (long i = 0; i < n; ++i)
        if (!fixed[static_cast<size_t>(i)])
            rhs[free_index[static_cast<size_t>(i)]] = f[i];
    for (int j = 0; j < n; ++j)
        for (SparseMatrix::InnerIterator it(K, j); it; ++it) {
            const int fi = free_index[static_cast<size_t>(it.row())];
            const int fj = free_index[static_cast<size_t>(j)];
            if (fi < 0)
                continue;
            if (fj >= 0)
                triplets.emplace_back(fi, fj, it.value());
            else
                rhs[fi] -= it.value() * u0[j]; // K_fc u_c to the right-hand side
        }
    SparseMatrix Kff(m, m);
    Kff.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(Kff);
    const Vector uf = ldlt.solve(rhs);
    Vector u = u0;
    for (long i = 0; i < n; ++i)
        if (!fixed[static_cast<size_t>(i)])
            u[i] = uf[free_index[static_cast<size_t>(i)]];
    return u;
}

} // namespace

TEST(CgRelaxation, SpringChainWithFixedEndsMatchesAnalyticSolution) {
    // 1D chain of 11 unit springs, ends fixed at 0 and 1, no load: u_i = i / 10 (linear)
    const int n = 11;
    const StiffnessProduct apply_K = [&](const Vector& x, Vector& Kx) {
        Kx.setZero();
        for (int e = 0; e + 1 < n; ++e) {
            const double stretch = x[e + 1] - x[e];
            Kx[e] -= stretch;
            Kx[e + 1] += stretch;
        }
    };
    std::vector<bool> fixed(n, false);
    fixed.front() = fixed.back() = true;
    Vector u = Vector::Zero(n);
    u[n - 1] = 1.0;
    const RelaxationResult r = cg_relax(apply_K, Vector::Zero(n), fixed, u, 1e-12, 100);
    EXPECT_TRUE(r.converged);
    EXPECT_LE(r.iterations, n - 2); // CG terminates in at most #free steps
    for (int i = 0; i < n; ++i)
        EXPECT_NEAR(u[i], i / 10.0, 1e-12) << i;
}

TEST(CgRelaxation, GridWithFixedFaceMatchesDirectSolve) {
    const int nx = 8, ny = 6, nz = 5;
    const SparseMatrix K = grid_matrix(nx, ny, nz, 0.0); // singular without the fixed face
    const long n = K.rows();
    std::vector<bool> fixed(static_cast<size_t>(n), false);
    Vector u0 = Vector::Zero(n);
    const Vector prescribed = random_vector(n, 70);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j) {
            const int node = (k * ny + j) * nx; // i = 0 face
            for (int c = 0; c < 3; ++c) {
                fixed[static_cast<size_t>(3 * node + c)] = true;
                u0[3 * node + c] = 0.01 * prescribed[3 * node + c];
            }
        }
    const Vector f = random_vector(n, 71);
    const Vector u_ref = reduced_solve(K, f, fixed, u0);

    CgRelaxation relaxation;
    const StiffnessProduct apply_K = [&](const Vector& x, Vector& Kx) { Kx = K * x; };
    Vector u = u0;
    const RelaxationResult r = relaxation.relax(apply_K, f, fixed, u, 1e-10, 5000);
    ASSERT_TRUE(r.converged);
    EXPECT_FALSE(r.breakdown);
    EXPECT_LT(r.relative_residual, 1e-9);
    EXPECT_GT(r.iterations, 10);
    // fixed DOFs untouched, bit for bit
    for (long i = 0; i < n; ++i) {
        if (fixed[static_cast<size_t>(i)]) {
            EXPECT_EQ(u[i], u0[i]) << i;
        }
    }
    // lambda_min of the clamped grid is ~ 1 / nx^2: forward error <= ~1e3 * residual
    EXPECT_LT((u - u_ref).norm() / u_ref.norm(), 1e-7);

    // warm start from the converged state: converged with zero iterations
    const RelaxationResult again = relaxation.relax(apply_K, f, fixed, u, 1e-8, 5000);
    EXPECT_TRUE(again.converged);
    EXPECT_EQ(again.iterations, 0);
}

TEST(CgRelaxation, PrescribedMotionOnlyUsesInitialResidualAsReference) {
    const SparseMatrix K = grid_matrix(4, 4, 4, 0.0);
    const long n = K.rows();
    std::vector<bool> fixed(static_cast<size_t>(n), false);
    Vector u = Vector::Zero(n);
    for (int c = 0; c < 3; ++c) {
        fixed[static_cast<size_t>(c)] = true; // node 0
        fixed[static_cast<size_t>(n - 3 + c)] = true; // last node, pulled
        u[n - 3 + c] = 0.1;
    }
    // the spring blocks k (0.5 I + d d^T) resist rotations too, so two fixed nodes suffice
    const StiffnessProduct apply_K = [&](const Vector& x, Vector& Kx) { Kx = K * x; };
    const Vector f = Vector::Zero(n);
    const Vector u_ref = reduced_solve(K, f, fixed, u);
    const RelaxationResult r = cg_relax(apply_K, f, fixed, u, 1e-10, 2000);
    ASSERT_TRUE(r.converged);
    EXPECT_LT((u - u_ref).norm() / u_ref.norm(), 1e-8);
}
