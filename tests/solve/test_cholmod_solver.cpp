// CHOLMOD LL^T: accuracy against Eigen's SimplicialLDLT, indefinite detection, re-analysis on a
// pattern change, non-finite input.
#include "grid_matrix.hpp"
#include "polycut/solve/blas_threads.hpp"
#include "polycut/solve/cholmod_solver.hpp"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdlib>
#include <gtest/gtest.h>
#include <limits>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

double relative_residual(const SparseMatrix& A, const Vector& x, const Vector& b) {
    return (b - A * x).norm() / b.norm();
}

} // namespace

TEST(CholmodSolver, SolvesSpdSystemLikeEigenLdlt) {
    const SparseMatrix A = grid_matrix(10, 10, 10, 1e-2); // 3,000 DOFs
    const Vector b = random_vector(A.rows(), 7);
    CholmodSolver solver;
    EXPECT_FALSE(solver.ready());
    ASSERT_EQ(solver.factorize(A), SolveStatus::Ok);
    EXPECT_TRUE(solver.ready());
    EXPECT_EQ(solver.size(), A.rows());
    EXPECT_GT(solver.factor_nonzeros(), A.nonZeros() / 2);
    Vector x;
    ASSERT_EQ(solver.solve(b, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(A, x, b), 1e-10);

    Eigen::SimplicialLDLT<SparseMatrix> ldlt(A);
    ASSERT_EQ(ldlt.info(), Eigen::Success);
    const Vector x_ref = ldlt.solve(b);
    // cond(A) <= ~27 / 1e-2: agreement to ~1e-16 * cond
    EXPECT_LT((x - x_ref).norm() / x_ref.norm(), 1e-10);

    // repeated solves reuse the workspace and give the same answer
    Vector x2;
    ASSERT_EQ(solver.solve(b, x2), SolveStatus::Ok);
    EXPECT_EQ((x2 - x).norm(), 0.0);
}

TEST(CholmodSolver, OrderingsGiveTheSameSolution) {
    const SparseMatrix A = grid_matrix(7, 8, 9, 1e-2);
    const Vector b = random_vector(A.rows(), 8);
    Vector x[3];
    long fill[3] = {};
    const Ordering orderings[3] = { Ordering::Auto, Ordering::Amd, Ordering::Metis };
    for (int k = 0; k < 3; ++k) {
        CholmodSolver solver(orderings[k]);
        ASSERT_EQ(solver.factorize(A), SolveStatus::Ok);
        ASSERT_EQ(solver.solve(b, x[k]), SolveStatus::Ok);
        EXPECT_LT(relative_residual(A, x[k], b), 1e-10);
        fill[k] = solver.factor_nonzeros();
    }
    EXPECT_LT((x[1] - x[2]).norm(), 1e-10 * x[2].norm());
    // Auto keeps the better of AMD and METIS
    EXPECT_LE(fill[0], std::max(fill[1], fill[2]));
}

TEST(CholmodSolver, BlasRunsSingleThreadedByDefault) {
    CholmodSolver solver;
    const int threads = blas_threads();
    if (threads == 0)
        GTEST_SKIP() << "BLAS is not OpenBLAS";
    if (std::getenv("OPENBLAS_NUM_THREADS"))
        GTEST_SKIP() << "OPENBLAS_NUM_THREADS is set";
    EXPECT_EQ(threads, 1);
}

TEST(CholmodSolver, IndefiniteMatrixIsReportedAndNeverSolved) {
    // lambda_min(K) = shift: a negative shift makes the three translation modes negative
    const SparseMatrix indefinite = grid_matrix(6, 6, 6, -1e-3);
    const Vector b = random_vector(indefinite.rows(), 3);
    CholmodSolver solver;
    EXPECT_EQ(solver.factorize(indefinite), SolveStatus::NotPositiveDefinite);
    EXPECT_FALSE(solver.ready());
    Vector x;
    EXPECT_EQ(solver.solve(b, x), SolveStatus::NotReady);
    EXPECT_EQ(x.size(), 0);

    // the same pattern with a positive shift factors again, without a new analysis
    const SparseMatrix spd = grid_matrix(6, 6, 6, 1e-3);
    ASSERT_EQ(solver.factorize(spd), SolveStatus::Ok);
    EXPECT_EQ(solver.analyses(), 1);
    ASSERT_EQ(solver.solve(b, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(spd, x, b), 1e-10);
}

TEST(CholmodSolver, SingleNegativePivotIsReported) {
    SparseMatrix A = grid_matrix(4, 4, 4, 1.0);
    A.coeffRef(100, 100) = -1.0; // e_100^T A e_100 < 0
    CholmodSolver solver;
    EXPECT_EQ(solver.factorize(A), SolveStatus::NotPositiveDefinite);
    EXPECT_FALSE(solver.ready());
}

TEST(CholmodSolver, PatternChangeTriggersReanalysis) {
    CholmodSolver solver;
    const SparseMatrix A1 = grid_matrix(8, 8, 8, 1e-2, 1);
    ASSERT_EQ(solver.factorize(A1), SolveStatus::Ok);
    EXPECT_EQ(solver.analyses(), 1);

    // same pattern, new values: factorize only
    const SparseMatrix A2 = grid_matrix(8, 8, 8, 2e-2, 2);
    EXPECT_TRUE(solver.same_pattern(A2));
    ASSERT_EQ(solver.factorize(A2), SolveStatus::Ok);
    EXPECT_EQ(solver.analyses(), 1);

    // same size, one extra coupling: new pattern
    SparseMatrix A3 = A2;
    A3.coeffRef(0, 1000) += 0.01;
    A3.coeffRef(1000, 0) += 0.01;
    A3.makeCompressed();
    EXPECT_FALSE(solver.same_pattern(A3));
    ASSERT_EQ(solver.factorize(A3), SolveStatus::Ok);
    EXPECT_EQ(solver.analyses(), 2);
    const Vector b3 = random_vector(A3.rows(), 5);
    Vector x;
    ASSERT_EQ(solver.solve(b3, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(A3, x, b3), 1e-10);

    // new size
    const SparseMatrix A4 = grid_matrix(7, 8, 9, 1e-2, 3);
    ASSERT_EQ(solver.factorize(A4), SolveStatus::Ok);
    EXPECT_EQ(solver.analyses(), 3);
    EXPECT_EQ(solver.size(), A4.rows());
    const Vector b4 = random_vector(A4.rows(), 6);
    ASSERT_EQ(solver.solve(b4, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(A4, x, b4), 1e-10);
}

TEST(CholmodSolver, UncompressedInputIsAccepted) {
    SparseMatrix A = grid_matrix(5, 5, 5, 1e-1);
    A.uncompress();
    ASSERT_FALSE(A.isCompressed());
    CholmodSolver solver;
    ASSERT_EQ(solver.factorize(A), SolveStatus::Ok);
    const Vector b = random_vector(A.rows(), 9);
    Vector x;
    ASSERT_EQ(solver.solve(b, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(A, x, b), 1e-10);
}

TEST(CholmodSolver, NonFiniteInputIsReported) {
    SparseMatrix A = grid_matrix(4, 4, 4, 1e-1);
    CholmodSolver solver;
    ASSERT_EQ(solver.factorize(A), SolveStatus::Ok);
    Vector b = random_vector(A.rows(), 1);
    b[17] = std::numeric_limits<double>::quiet_NaN();
    Vector x;
    EXPECT_EQ(solver.solve(b, x), SolveStatus::NonFinite);
    b[17] = std::numeric_limits<double>::infinity();
    EXPECT_EQ(solver.solve(b, x), SolveStatus::NonFinite);

    A.coeffRef(3, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(solver.factorize(A), SolveStatus::NonFinite);
    EXPECT_FALSE(solver.ready());
}

TEST(CholmodSolver, MovedSolverKeepsItsFactor) {
    const SparseMatrix A = grid_matrix(4, 4, 4, 1e-1);
    CholmodSolver a;
    ASSERT_EQ(a.factorize(A), SolveStatus::Ok);
    CholmodSolver b = std::move(a);
    EXPECT_TRUE(b.ready());
    EXPECT_FALSE(a.ready()); // NOLINT(bugprone-use-after-move): moved-from is valid, empty
    const Vector rhs = random_vector(A.rows(), 2);
    Vector x;
    ASSERT_EQ(b.solve(rhs, x), SolveStatus::Ok);
    EXPECT_LT(relative_residual(A, x, rhs), 1e-10);
    // a moved-from solver can be used again
    ASSERT_EQ(a.factorize(A), SolveStatus::Ok);
    EXPECT_TRUE(a.ready());
}

TEST(SolveStatus, Names) {
    EXPECT_STREQ(to_string(SolveStatus::Ok), "ok");
    EXPECT_STREQ(to_string(SolveStatus::NotPositiveDefinite), "not_positive_definite");
    EXPECT_STREQ(to_string(SolveStatus::NotConverged), "not_converged");
    EXPECT_STREQ(to_string(SolveStatus::NonFinite), "non_finite");
    EXPECT_STREQ(to_string(SolveStatus::NotReady), "not_ready");
}

TEST(MultiplySymmetric, MatchesEigenProduct) {
    const SparseMatrix A = grid_matrix(5, 6, 7, 0.3);
    const Vector x = random_vector(A.rows(), 4);
    Vector y;
    multiply_symmetric(A, x, y);
    const Vector y_ref = A * x;
    EXPECT_LT((y - y_ref).norm(), 1e-13 * y_ref.norm());
}
