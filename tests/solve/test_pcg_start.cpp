// PCG's projected start (PcgOptions::start_vectors; Fischer 1998, core/solve/src/start_space.hpp):
// the start is the Galerkin projection of A x = b onto the span of the kept solutions.
#include "grid_matrix.hpp"
#include "polycut/common/error.hpp"
#include "polycut/solve/pcg.hpp"
#include "polycut/solve/sparse.hpp"

#include <Eigen/Cholesky>
#include <cstring>
#include <gtest/gtest.h>
#include <vector>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

constexpr double kShift = 1e-2;

PcgOptions options(int start_vectors, double tolerance = 1e-10) {
    PcgOptions o;
    o.relative_tolerance = tolerance;
    o.preconditioner = Preconditioner::Jacobi;
    o.max_iterations = 5000;
    o.start_vectors = start_vectors;
    return o;
}

/// Solves and returns the iterations (status Ok asserted).
int solve(PcgSolver& pcg, const SparseMatrix& A, const Vector& b, Vector& x) {
    const PcgResult r = pcg.solve(A, b, x);
    EXPECT_EQ(r.status, SolveStatus::Ok);
    return r.iterations;
}

} // namespace

TEST(PcgStart, ARightHandSideInTheSpanOfEarlierOnesIsSolvedByTheProjection) {
    // x_i solve A x_i = b_i to 1e-10; b = 0.5 b_1 - 2 b_2 + b_3 is solved by the same
    // combination of the x_i: the projected start meets a 1e-8 tolerance with no iteration,
    // where the plain start (the last solution) needs many.
    const SparseMatrix A = grid_matrix(8, 8, 8, kShift);
    const Vector b1 = random_vector(A.rows(), 1), b2 = random_vector(A.rows(), 2),
                 b3 = random_vector(A.rows(), 3);
    const Vector b = 0.5 * b1 - 2.0 * b2 + b3;
    for (const int k : { 0, 3 }) {
        PcgSolver pcg(options(k));
        Vector x = Vector::Zero(A.rows());
        for (const Vector* bi : { &b1, &b2, &b3 })
            EXPECT_GT(solve(pcg, A, *bi, x), 10);
        const PcgResult r = pcg.solve(A, b, x);
        ASSERT_EQ(r.status, SolveStatus::Ok);
        if (k == 0) {
            EXPECT_GT(r.iterations, 10);
        } else {
            EXPECT_EQ(r.iterations, 0);
            EXPECT_LE(Vector(b - A * x).norm(), 1e-8 * b.norm());
        }
    }
}

TEST(PcgStart, TheStartIsTheGalerkinProjectionOntoTheLastSolutions) {
    // With A unchanged the lagged products are exact: the start is x0 = V c with
    // V^T A V c = V^T b over the last 3 of 4 solutions (the ring drops the first). Its residual,
    // computed here densely, is the one PCG reports (1e-8 relative): the start was neither
    // dropped for zero by the energy test nor left at the given x; the solve then converges.
    const SparseMatrix A = grid_matrix(8, 8, 8, kShift);
    std::vector<Vector> kept;
    PcgSolver pcg(options(3));
    Vector x = Vector::Zero(A.rows());
    for (int i = 0; i < 4; ++i) {
        const Vector bi = random_vector(A.rows(), 10 + unsigned(i));
        solve(pcg, A, bi, x);
        kept.push_back(x);
    }
    kept.erase(kept.begin());
    Eigen::MatrixXd V(A.rows(), 3);
    for (int i = 0; i < 3; ++i)
        V.col(i) = kept[std::size_t(i)];
    const Vector b = random_vector(A.rows(), 99);
    const Eigen::MatrixXd AV = A * V;
    const Eigen::VectorXd c = (V.transpose() * AV).ldlt().solve(V.transpose() * b);
    const Vector x0 = V * c;
    const double expected = Vector(b - A * x0).norm() / b.norm();
    Vector y = Vector::Zero(A.rows());
    const PcgResult r = pcg.solve(A, b, y);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_NEAR(r.start_residual, expected, 1e-8 * expected);
    EXPECT_LE(Vector(b - A * y).norm(), 1e-10 * b.norm() * (1 + 1e-6));
}

TEST(PcgStart, AFamilyOfSlowlyTurningLoadsNeedsFewerIterations) {
    // b(t) = cos(t) b_1 + sin(t) b_2 + t b_3 / 10 at a loose tolerance (0.3, as the organ
    // scenes): the solutions span three directions, so once three are kept the projected start
    // meets the tolerance at once; the extrapolated start (2 x_{n-1} - x_{n-2}, passed in by
    // the caller) does not.
    const SparseMatrix A = grid_matrix(8, 8, 8, kShift);
    const Vector b1 = random_vector(A.rows(), 4), b2 = random_vector(A.rows(), 5),
                 b3 = random_vector(A.rows(), 6);
    int total[2] = { 0, 0 };
    for (const int k : { 0, 4 }) {
        PcgSolver pcg(options(k, 1e-3));
        Vector x = Vector::Zero(A.rows()), x_prev = x;
        for (int n = 0; n < 20; ++n) {
            const double t = 0.3 * n;
            const Vector b = std::cos(t) * b1 + std::sin(t) * b2 + 0.1 * t * b3;
            Vector guess = 2.0 * x - x_prev;
            total[k > 0] += solve(pcg, A, b, guess);
            x_prev = x;
            x = guess;
            EXPECT_LE(Vector(b - A * x).norm(), 1e-3 * b.norm() * (1 + 1e-9));
        }
    }
    EXPECT_LT(total[1], total[0] / 3);
}

TEST(PcgStart, ForgottenOrResizedSolutionsAreNotUsed) {
    const SparseMatrix A = grid_matrix(6, 6, 6, kShift);
    const Vector b = random_vector(A.rows(), 7);
    PcgSolver pcg(options(2));
    Vector x = Vector::Zero(A.rows());
    solve(pcg, A, b, x);
    Vector again = Vector::Zero(A.rows());
    EXPECT_EQ(solve(pcg, A, b, again), 0); // b's own solution is kept
    pcg.forget_solutions();
    again.setZero();
    EXPECT_GT(solve(pcg, A, b, again), 0);
    // a system of another size (a cut added unknowns): solved from its own start, correctly
    const SparseMatrix B = grid_matrix(7, 6, 6, kShift);
    const Vector c = random_vector(B.rows(), 8);
    Vector y = Vector::Zero(B.rows());
    EXPECT_GT(solve(pcg, B, c, y), 0);
    EXPECT_LE(Vector(c - B * y).norm(), 1e-10 * c.norm() * (1 + 1e-6));
}

TEST(PcgStart, TheKeptProductsInOnePassAreThoseOfOneMultiplyEach) {
    // multiply_symmetric_many (the kept solutions' products after a cut, one pass over A) gives
    // each product exactly as multiply_symmetric does, for 1, 4 and 32 vectors, on one and two
    // threads (the sums of a row in the same order); more than kMaxMultiply is refused.
    const SparseMatrix A = grid_matrix(7, 6, 5, kShift);
    for (const std::size_t m : { std::size_t(1), std::size_t(4), kMaxMultiply })
        for (const int threads : { 1, 2 }) {
            std::vector<Vector> xs, ys(m), one(m);
            for (std::size_t i = 0; i < m; ++i)
                xs.push_back(random_vector(A.rows(), unsigned(40 + i)));
            multiply_symmetric_many(A, xs, ys, threads);
            for (std::size_t i = 0; i < m; ++i) {
                multiply_symmetric(A, xs[i], one[i], threads);
                ASSERT_EQ(ys[i].size(), A.rows());
                EXPECT_EQ(std::memcmp(
                              ys[i].data(), one[i].data(), sizeof(double) * std::size_t(A.rows())),
                    0)
                    << m << " vectors, " << threads << " threads, vector " << i;
            }
        }
    std::vector<Vector> many(kMaxMultiply + 1, Vector::Ones(A.rows())), out(kMaxMultiply + 1);
    EXPECT_THROW(multiply_symmetric_many(A, many, out), polycut::InputError);
}
