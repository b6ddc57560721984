// PCG's iteration budget (PcgOptions::iteration_budget): a solve stops after that many iterations
// with status Ok and its iterate, which PCG's minimization keeps no further from the solution in
// the A-norm than the start, and closer with every iteration the budget allows.
#include "grid_matrix.hpp"
#include "polycut/solve/pcg.hpp"

#include <Eigen/Cholesky>
#include <cstring>
#include <gtest/gtest.h>
#include <vector>

using namespace polycut::solve;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

PcgOptions options(int budget) {
    PcgOptions o;
    o.relative_tolerance = 1e-10;
    o.preconditioner = Preconditioner::Jacobi;
    o.max_iterations = 5000;
    o.iteration_budget = budget;
    return o;
}

/// ||x - x*||_A for A's dense solution x*.
double energy_error(const SparseMatrix& A, const Vector& exact, const Vector& x) {
    const Vector e = x - exact;
    return std::sqrt(e.dot(A * e));
}

} // namespace

TEST(PcgBudget, StopsAtTheBudgetWithAnIterateThatOnlyGetsBetter) {
    // A 6 x 6 x 6 grid Laplacian + shift needs tens of Jacobi-PCG iterations to 1e-10. With a
    // budget of k = 1..8 the solve stops after exactly k iterations, Ok, budget_reached; its
    // reported residual is the true one (to 1e-8 relative), and the A-norm error decreases
    // strictly with k from the start's (PCG minimizes it over the growing Krylov space), from a
    // zero start and from a nonzero one.
    const SparseMatrix A = grid_matrix(6, 6, 6, 1e-2);
    const Vector b = random_vector(A.rows(), 5);
    const Vector exact = Eigen::MatrixXd(A).llt().solve(b);
    for (const bool zero_start : { true, false }) {
        const Vector x0 = zero_start ? Vector(Vector::Zero(A.rows()))
                                     : Vector(0.5 * exact + 1e-3 * random_vector(A.rows(), 6));
        double previous = energy_error(A, exact, x0);
        for (int k = 1; k <= 8; ++k) {
            PcgSolver pcg(options(k));
            Vector x = x0;
            const PcgResult r = pcg.solve(A, b, x);
            ASSERT_EQ(r.status, SolveStatus::Ok) << k;
            EXPECT_TRUE(r.budget_reached) << k;
            EXPECT_EQ(r.iterations, k);
            const double true_residual = (b - A * x).norm() / b.norm();
            EXPECT_NEAR(r.relative_residual, true_residual, 1e-8 * true_residual) << k;
            EXPECT_GT(r.relative_residual, 1e-10) << k;
            const double err = energy_error(A, exact, x);
            EXPECT_LT(err, previous) << "budget " << k << (zero_start ? " zero" : " warm");
            previous = err;
        }
    }
}

TEST(PcgBudget, ABudgetTheSolveDoesNotReachChangesNothing) {
    // The unbudgeted solve needs n iterations; with a budget of n (the tolerance is met at the
    // n-th, before the budget is looked at) or more, the solution is the same to the bit and
    // budget_reached stays false; a budget of n - 1 stops one short.
    const SparseMatrix A = grid_matrix(6, 6, 6, 1e-2);
    const Vector b = random_vector(A.rows(), 7);
    Vector free_x;
    PcgSolver free_pcg(options(0));
    const PcgResult free_r = free_pcg.solve(A, b, free_x);
    ASSERT_EQ(free_r.status, SolveStatus::Ok);
    EXPECT_FALSE(free_r.budget_reached);
    const int n = free_r.iterations;
    ASSERT_GT(n, 5);
    for (const int budget : { n, n + 10 }) {
        PcgSolver pcg(options(budget));
        Vector x;
        const PcgResult r = pcg.solve(A, b, x);
        ASSERT_EQ(r.status, SolveStatus::Ok);
        EXPECT_FALSE(r.budget_reached) << budget;
        EXPECT_EQ(r.iterations, n);
        EXPECT_EQ(std::memcmp(x.data(), free_x.data(), sizeof(double) * std::size_t(x.size())), 0);
    }
    PcgSolver short_pcg(options(n - 1));
    Vector x;
    const PcgResult r = short_pcg.solve(A, b, x);
    EXPECT_TRUE(r.budget_reached);
    EXPECT_EQ(r.iterations, n - 1);
    EXPECT_GT(r.relative_residual, 1e-10);
}
