// BackgroundCholesky: the worker's factor equals a foreground one; newer jobs supersede older
// ones; cancel and destruction while busy are safe.
#include "grid_matrix.hpp"
#include "polycut/solve/background_cholesky.hpp"

#include <gtest/gtest.h>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

TEST(BackgroundCholesky, SameSolutionAsForegroundFactorization) {
    const SparseMatrix A = grid_matrix(9, 9, 9, 1e-2);
    const Vector b = random_vector(A.rows(), 80);
    CholmodSolver foreground;
    ASSERT_EQ(foreground.factorize(A), SolveStatus::Ok);
    Vector x_fg;
    ASSERT_EQ(foreground.solve(b, x_fg), SolveStatus::Ok);

    BackgroundCholesky background;
    EXPECT_FALSE(background.busy());
    EXPECT_FALSE(background.ready());
    background.start(A);
    background.wait();
    EXPECT_FALSE(background.busy());
    ASSERT_TRUE(background.ready());
    EXPECT_EQ(background.status(), SolveStatus::Ok);
    std::optional<CholmodSolver> solver = background.take();
    ASSERT_TRUE(solver.has_value());
    EXPECT_FALSE(background.ready());
    EXPECT_FALSE(background.take().has_value());
    Vector x_bg;
    ASSERT_EQ(solver->solve(b, x_bg), SolveStatus::Ok);
    // same ordering, same arithmetic
    EXPECT_LE((x_bg - x_fg).norm(), 1e-14 * x_fg.norm());
}

TEST(BackgroundCholesky, NewerJobSupersedesOlder) {
    const SparseMatrix big = grid_matrix(12, 12, 12, 1e-2);
    const SparseMatrix small = grid_matrix(5, 5, 5, 1e-2);
    BackgroundCholesky background;
    background.start(big);
    background.start(small);
    EXPECT_EQ(background.size(), small.rows());
    background.wait();
    std::optional<CholmodSolver> solver = background.take();
    ASSERT_TRUE(solver.has_value());
    EXPECT_EQ(solver->size(), small.rows());
    const Vector b = random_vector(small.rows(), 81);
    Vector x;
    ASSERT_EQ(solver->solve(b, x), SolveStatus::Ok);
    EXPECT_LT((b - small * x).norm(), 1e-10 * b.norm());
}

TEST(BackgroundCholesky, ReusedSolverKeepsItsAnalysis) {
    const SparseMatrix A = grid_matrix(6, 6, 6, 1e-2, 1);
    const SparseMatrix B = grid_matrix(6, 6, 6, 2e-2, 2); // same pattern
    BackgroundCholesky background;
    background.start(A);
    background.wait();
    std::optional<CholmodSolver> solver = background.take();
    ASSERT_TRUE(solver.has_value());
    background.start(B, std::move(*solver));
    background.wait();
    solver = background.take();
    ASSERT_TRUE(solver.has_value());
    EXPECT_EQ(solver->analyses(), 1);
    const Vector b = random_vector(B.rows(), 82);
    Vector x;
    ASSERT_EQ(solver->solve(b, x), SolveStatus::Ok);
    EXPECT_LT((b - B * x).norm(), 1e-10 * b.norm());
}

TEST(BackgroundCholesky, IndefiniteMatrixGivesNoFactor) {
    BackgroundCholesky background;
    background.start(grid_matrix(5, 5, 5, -1e-3));
    background.wait();
    EXPECT_TRUE(background.ready());
    EXPECT_EQ(background.status(), SolveStatus::NotPositiveDefinite);
    EXPECT_FALSE(background.take().has_value());
}

TEST(BackgroundCholesky, CancelAndDestroyWhileBusy) {
    const SparseMatrix big = grid_matrix(12, 12, 12, 1e-2);
    {
        BackgroundCholesky background;
        background.start(big);
        background.cancel();
        EXPECT_FALSE(background.ready());
        background.wait(); // returns: the cancelled job is not waited for
        EXPECT_FALSE(background.ready());
        EXPECT_FALSE(background.take().has_value());
        background.start(big);
    } // destroyed while (probably) factoring: joins
    SUCCEED();
}
