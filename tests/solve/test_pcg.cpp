// PCG: every preconditioner reaches the tolerance and agrees with CHOLMOD within the
// condition-number bound; warm starts; lagged factor schedule; background refactorization.
#include "grid_matrix.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <gtest/gtest.h>
#include <limits>

using namespace polycut::solve;
using polycut::solve::testing::gershgorin_bound;
using polycut::solve::testing::grid_matrix;
using polycut::solve::testing::random_vector;

namespace {

constexpr double kShift = 1e-2;

Vector direct_solution(const SparseMatrix& A, const Vector& b) {
    CholmodSolver solver;
    EXPECT_EQ(solver.factorize(A), SolveStatus::Ok);
    Vector x;
    EXPECT_EQ(solver.solve(b, x), SolveStatus::Ok);
    return x;
}

/// The grid matrix with each value scaled by 1 + eps u, u in [-1, 1] symmetric per pair:
/// same pattern, slightly different stiffness (a "later time step").
SparseMatrix perturbed(const SparseMatrix& A, double eps) {
    SparseMatrix B = A;
    const SparseMatrix noise = grid_matrix(static_cast<int>(std::cbrt(A.rows() / 3.0) + 0.5),
        static_cast<int>(std::cbrt(A.rows() / 3.0) + 0.5),
        static_cast<int>(std::cbrt(A.rows() / 3.0) + 0.5), kShift, 99);
    B = A + eps * noise; // a sum of SPD matrices: SPD, same pattern
    B.makeCompressed();
    return B;
}

class PcgPreconditioners : public ::testing::TestWithParam<Preconditioner> { };

} // namespace

TEST_P(PcgPreconditioners, ReachesToleranceAndAgreesWithCholmod) {
    const SparseMatrix A = grid_matrix(10, 10, 10, kShift);
    const Vector b = random_vector(A.rows(), 11);
    const Vector x_ref = direct_solution(A, b);
    const double condition_bound = gershgorin_bound(A) / kShift; // lambda_min = shift exactly

    PcgOptions options;
    options.preconditioner = GetParam();
    options.relative_tolerance = 1e-8;
    options.max_iterations = 5000;
    PcgSolver pcg(options);
    Vector x = Vector::Zero(A.rows());
    const PcgResult result = pcg.solve(A, b, x);
    ASSERT_EQ(result.status, SolveStatus::Ok) << to_string(result.status);
    EXPECT_EQ(result.used, GetParam());
    EXPECT_GT(result.iterations, 0);
    EXPECT_LE(result.relative_residual, 1.01 * options.relative_tolerance);
    EXPECT_NEAR(result.relative_residual, (b - A * x).norm() / b.norm(), 1e-15);
    // forward error <= cond(A) * relative residual
    EXPECT_LE((x - x_ref).norm() / x_ref.norm(), condition_bound * result.relative_residual);
    if (GetParam() == Preconditioner::LaggedCholesky) {
        EXPECT_TRUE(result.refactored);
        EXPECT_LE(result.iterations, 2); // the exact factor of A
    }
}

INSTANTIATE_TEST_SUITE_P(All, PcgPreconditioners,
    ::testing::Values(Preconditioner::None, Preconditioner::Jacobi, Preconditioner::BlockJacobi3,
        Preconditioner::LaggedCholesky),
    [](const ::testing::TestParamInfo<Preconditioner>& param_info) {
        return std::string(to_string(param_info.param));
    });

TEST(Pcg, BlockJacobiIsExactOnBlockDiagonalMatrix) {
    // 100 random SPD 3x3 node blocks, strongly coupled within the node, none between nodes:
    // M^-1 = A^-1 for BlockJacobi3, so PCG converges in one iteration; Jacobi cannot.
    const int nodes = 100;
    std::vector<Eigen::Triplet<double, int>> triplets;
    for (int i = 0; i < nodes; ++i) {
        const Vector g = random_vector(9, 200 + i);
        const Eigen::Matrix3d G = Eigen::Map<const Eigen::Matrix3d>(g.data());
        const Eigen::Matrix3d block = G * G.transpose() + 0.1 * Eigen::Matrix3d::Identity();
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                triplets.emplace_back(3 * i + r, 3 * i + c, block(r, c));
    }
    SparseMatrix A(3 * nodes, 3 * nodes);
    A.setFromTriplets(triplets.begin(), triplets.end());
    const Vector b = random_vector(A.rows(), 12);
    PcgSolver block_jacobi(
        { .relative_tolerance = 1e-10, .preconditioner = Preconditioner::BlockJacobi3 });
    Vector x;
    PcgResult r = block_jacobi.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.iterations, 1);
    EXPECT_LT(r.relative_residual, 1e-12);

    PcgSolver jacobi({ .relative_tolerance = 1e-10, .preconditioner = Preconditioner::Jacobi });
    x.setZero();
    r = jacobi.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_GT(r.iterations, 1);
}

TEST(Pcg, CellBlockJacobiIsExactOnItsBlocksAndFallsBackWithoutThem) {
    // Blocks of 12, 30 and 12 unknowns (DG cells of degree 1, 2, 1), SPD and dense inside,
    // none between them: with the blocks set, PCG converges in one iteration; without them
    // it runs as 3x3 block Jacobi and needs more.
    const std::vector<long> starts = { 0, 12, 42, 54 };
    std::vector<Eigen::Triplet<double, int>> triplets;
    for (std::size_t k = 0; k + 1 < starts.size(); ++k) {
        const int s = int(starts[k]), n = int(starts[k + 1] - starts[k]);
        const Vector g = random_vector(n * n, 300 + int(k));
        const Eigen::MatrixXd G = Eigen::Map<const Eigen::MatrixXd>(g.data(), n, n);
        const Eigen::MatrixXd block = G * G.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
        for (int r = 0; r < n; ++r)
            for (int c = 0; c < n; ++c)
                triplets.emplace_back(s + r, s + c, block(r, c));
    }
    SparseMatrix A(54, 54);
    A.setFromTriplets(triplets.begin(), triplets.end());
    const Vector b = random_vector(A.rows(), 13);
    PcgSolver cells({ .relative_tolerance = 1e-10, .preconditioner = Preconditioner::BlockJacobi });
    Vector x;
    PcgResult r = cells.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.used, Preconditioner::BlockJacobi3); // no blocks yet
    EXPECT_GT(r.iterations, 1);
    cells.set_blocks(starts);
    x.setZero();
    r = cells.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.used, Preconditioner::BlockJacobi);
    EXPECT_EQ(r.iterations, 1);
    EXPECT_LT(r.relative_residual, 1e-12);
}

TEST(Pcg, WarmStart) {
    const SparseMatrix A = grid_matrix(10, 10, 10, kShift);
    const Vector b = random_vector(A.rows(), 13);
    const Vector x_ref = direct_solution(A, b);
    PcgSolver pcg({ .relative_tolerance = 1e-8, .preconditioner = Preconditioner::Jacobi });

    Vector x = x_ref;
    PcgResult r = pcg.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ((x - x_ref).norm(), 0.0);

    Vector x_zero = Vector::Zero(A.rows());
    const int from_zero = pcg.solve(A, b, x_zero).iterations;
    Vector x_near
        = x_ref + 1e-4 * x_ref.norm() / std::sqrt(double(A.rows())) * random_vector(A.rows(), 14);
    const int from_near = pcg.solve(A, b, x_near).iterations;
    EXPECT_LT(from_near, from_zero);
    EXPECT_GT(from_near, 0);
}

TEST(Pcg, AGuessWorseThanZeroIsDroppedAndABetterOneKept) {
    // Decision 0061: x0 is kept only if E(x0) = x0.A x0 / 2 - b.x0 < 0 (closer to the answer
    // than zero in the A-norm PCG minimizes); else the solve starts from zero.
    const SparseMatrix A = grid_matrix(10, 10, 10, kShift);
    const Vector b = random_vector(A.rows(), 21);
    const Vector x_ref = direct_solution(A, b);
    PcgSolver pcg({ .relative_tolerance = 1e-8, .preconditioner = Preconditioner::Jacobi });
    Vector x_zero = Vector::Zero(A.rows());
    const PcgResult zero = pcg.solve(A, b, x_zero);
    ASSERT_EQ(zero.status, SolveStatus::Ok);

    // -x*: E = 3/2 b.x* > 0 (a step whose motion reversed): the same solve as from zero
    Vector x_bad = -x_ref;
    const PcgResult bad = pcg.solve(A, b, x_bad);
    ASSERT_EQ(bad.status, SolveStatus::Ok);
    EXPECT_EQ(bad.iterations, zero.iterations);
    EXPECT_EQ((x_bad - x_zero).norm(), 0.0);

    // x* / 2: E = -3/8 b.x* < 0: kept (another Krylov path, the same tolerance)
    Vector x_half = 0.5 * x_ref;
    const PcgResult half = pcg.solve(A, b, x_half);
    ASSERT_EQ(half.status, SolveStatus::Ok);
    EXPECT_GT((x_half - x_zero).norm(), 0.0);
    EXPECT_LE(half.iterations, zero.iterations);
    EXPECT_LE(Vector(A * x_half - b).norm(), 1e-8 * b.norm() * (1 + 1e-9));
}

TEST(Pcg, ZeroRightHandSideGivesZero) {
    const SparseMatrix A = grid_matrix(4, 4, 4, kShift);
    PcgSolver pcg;
    Vector x = Vector::Ones(A.rows());
    const PcgResult r = pcg.solve(A, Vector::Zero(A.rows()), x);
    EXPECT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(x.norm(), 0.0);
}

TEST(Pcg, IterationLimitIsReported) {
    const SparseMatrix A = grid_matrix(8, 8, 8, kShift);
    PcgSolver pcg({ .relative_tolerance = 1e-12,
        .max_iterations = 3,
        .preconditioner = Preconditioner::None });
    Vector x;
    const Vector b = random_vector(A.rows(), 15);
    const PcgResult r = pcg.solve(A, b, x);
    EXPECT_EQ(r.status, SolveStatus::NotConverged);
    EXPECT_EQ(r.iterations, 3);
    EXPECT_GT(r.relative_residual, 1e-12);
    EXPECT_LT(r.relative_residual, 1.0); // three CG steps do reduce the residual
}

TEST(Pcg, NonFiniteRightHandSide) {
    const SparseMatrix A = grid_matrix(4, 4, 4, kShift);
    Vector b = random_vector(A.rows(), 16);
    b[5] = std::numeric_limits<double>::quiet_NaN();
    for (Preconditioner p : { Preconditioner::Jacobi, Preconditioner::LaggedCholesky }) {
        PcgSolver pcg({ .preconditioner = p });
        Vector x;
        EXPECT_EQ(pcg.solve(A, b, x).status, SolveStatus::NonFinite);
    }
}

TEST(Pcg, IndefiniteMatrixIsReported) {
    const SparseMatrix A = grid_matrix(5, 5, 5, -1e-3);
    const Vector b = random_vector(A.rows(), 17);
    for (Preconditioner p : { Preconditioner::None, Preconditioner::LaggedCholesky }) {
        PcgSolver pcg(
            { .relative_tolerance = 1e-12, .max_iterations = 10000, .preconditioner = p });
        Vector x;
        EXPECT_EQ(pcg.solve(A, b, x).status, SolveStatus::NotPositiveDefinite) << to_string(p);
    }
}

TEST(Pcg, LaggedFactorOfNearbyMatrixConvergesFast) {
    const SparseMatrix A0 = grid_matrix(10, 10, 10, kShift);
    PcgSolver pcg({ .relative_tolerance = 1e-8,
        .preconditioner = Preconditioner::LaggedCholesky,
        .refactor_every = 0,
        .refactor_iterations = 50 });
    Vector x;
    PcgResult r = pcg.solve(A0, random_vector(A0.rows(), 18), x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_TRUE(r.refactored);

    // 2 % stiffer in places: the factor of A0 preconditions A1 to within a few iterations
    const SparseMatrix A1 = perturbed(A0, 0.02);
    const Vector b1 = random_vector(A1.rows(), 19);
    r = pcg.solve(A1, b1, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_FALSE(r.refactored);
    EXPECT_LT(r.iterations, 10);
    EXPECT_LE(r.relative_residual, 1.01e-8);
    EXPECT_LT((x - direct_solution(A1, b1)).norm() / x.norm(), 1e-5);
    EXPECT_EQ(pcg.refactorizations(), 1);
}

TEST(Pcg, LaggedFactorIsRefreshedOnSchedule) {
    const SparseMatrix A = grid_matrix(6, 6, 6, kShift);
    PcgSolver pcg({ .relative_tolerance = 1e-8,
        .preconditioner = Preconditioner::LaggedCholesky,
        .refactor_every = 3,
        .refactor_iterations = 1000 });
    Vector x;
    std::vector<bool> refactored;
    for (int step = 0; step < 7; ++step) {
        const SparseMatrix As = perturbed(A, 0.01 * step);
        refactored.push_back(pcg.solve(As, random_vector(A.rows(), 20 + step), x).refactored);
    }
    EXPECT_EQ(refactored, (std::vector<bool> { true, false, false, true, false, false, true }));
    EXPECT_EQ(pcg.refactorizations(), 3);
}

TEST(Pcg, LaggedFactorIsRefreshedWhenIterationsGrow) {
    const SparseMatrix A = grid_matrix(6, 6, 6, kShift);
    PcgSolver pcg({ .relative_tolerance = 1e-10,
        .preconditioner = Preconditioner::LaggedCholesky,
        .refactor_every = 0,
        .refactor_iterations = 2 });
    Vector x;
    EXPECT_TRUE(pcg.solve(A, random_vector(A.rows(), 30), x).refactored);
    // a much stiffer matrix: the old factor needs more than 2 iterations...
    const SparseMatrix B = perturbed(A, 1.0);
    const PcgResult r1 = pcg.solve(B, random_vector(A.rows(), 31), x);
    EXPECT_FALSE(r1.refactored);
    EXPECT_GT(r1.iterations, 2);
    // ...so the next solve refactors, and then needs at most one or two
    const PcgResult r2 = pcg.solve(B, random_vector(A.rows(), 32), x);
    EXPECT_TRUE(r2.refactored);
    EXPECT_LE(r2.iterations, 2);
}

TEST(Pcg, StaleFactorThatCannotConvergeIsRefreshedWithinTheSolve) {
    const SparseMatrix A = grid_matrix(6, 6, 6, kShift);
    PcgSolver pcg({ .relative_tolerance = 1e-10,
        .max_iterations = 3,
        .preconditioner = Preconditioner::LaggedCholesky,
        .refactor_iterations = 1000 });
    Vector x;
    ASSERT_EQ(pcg.solve(A, random_vector(A.rows(), 33), x).status, SolveStatus::Ok);
    // the factor of A cannot bring B to 1e-10 in 3 iterations: refactor once, then converge
    const SparseMatrix B = perturbed(A, 3.0);
    const Vector b = random_vector(B.rows(), 34);
    x.setZero();
    const PcgResult r = pcg.solve(B, b, x);
    EXPECT_EQ(r.status, SolveStatus::Ok);
    EXPECT_TRUE(r.refactored);
    EXPECT_GT(r.iterations, 3);
    EXPECT_LE(r.relative_residual, 1.01e-10);
    EXPECT_EQ(pcg.refactorizations(), 2);
}

TEST(Pcg, LaggedFactorIsRefreshedOnPatternOrSizeChange) {
    PcgSolver pcg({ .preconditioner = Preconditioner::LaggedCholesky });
    Vector x;
    const SparseMatrix A = grid_matrix(5, 5, 5, kShift);
    EXPECT_TRUE(pcg.solve(A, random_vector(A.rows(), 40), x).refactored);
    EXPECT_FALSE(pcg.solve(A, random_vector(A.rows(), 41), x).refactored);
    const SparseMatrix B = grid_matrix(5, 5, 6, kShift);
    const PcgResult r = pcg.solve(B, random_vector(B.rows(), 42), x);
    EXPECT_TRUE(r.refactored);
    EXPECT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(x.size(), B.rows());
}

TEST(Pcg, BackgroundRefactorKeepsSteppingAndInstallsTheFactor) {
    PcgSolver pcg({ .relative_tolerance = 1e-8,
        .preconditioner = Preconditioner::LaggedCholesky,
        .background_refactor = true });
    const SparseMatrix A = grid_matrix(8, 8, 8, kShift);
    const Vector b = random_vector(A.rows(), 50);
    const Vector x_ref = direct_solution(A, b);
    Vector x;
    // no factor yet: the first solve runs with block Jacobi while the worker factors A
    PcgResult r = pcg.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.used, Preconditioner::BlockJacobi3);
    EXPECT_FALSE(r.refactored);
    pcg.finish_background_refactor();
    x.setZero();
    r = pcg.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.used, Preconditioner::LaggedCholesky);
    EXPECT_TRUE(r.refactored);
    EXPECT_LE(r.iterations, 2);
    EXPECT_LT((x - x_ref).norm() / x_ref.norm(), 1e-6);

    // a "cut" changes the size: block Jacobi until the new factor is in
    const SparseMatrix B = grid_matrix(8, 8, 9, kShift);
    const Vector bb = random_vector(B.rows(), 51);
    r = pcg.solve(B, bb, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_EQ(r.used, Preconditioner::BlockJacobi3);
    pcg.finish_background_refactor();
    r = pcg.solve(B, bb, x);
    EXPECT_EQ(r.used, Preconditioner::LaggedCholesky);
    EXPECT_TRUE(r.refactored);
    EXPECT_EQ(pcg.refactorizations(), 2);
}

TEST(Pcg, InstalledFactorIsUsed) {
    const SparseMatrix A = grid_matrix(6, 6, 6, kShift);
    CholmodSolver factor;
    ASSERT_EQ(factor.factorize(A), SolveStatus::Ok);
    PcgSolver pcg({ .preconditioner = Preconditioner::LaggedCholesky });
    pcg.set_preconditioner_factor(std::move(factor));
    Vector x;
    const PcgResult r = pcg.solve(A, random_vector(A.rows(), 60), x);
    EXPECT_TRUE(r.refactored);
    EXPECT_LE(r.iterations, 2);
    EXPECT_EQ(pcg.refactorizations(), 0); // installed, not factored by the solver
}

TEST(Sparse, ScaleShiftMultiplyFormsTheSystemAndTheProductInOnePass) {
    // A = a K + diag(d) on K's pattern and y = K x, against Eigen's expressions (round-off only)
    const SparseMatrix K = grid_matrix(5, 4, 3, 0.1);
    const Vector x = random_vector(K.rows(), 11);
    const Vector d = random_vector(K.rows(), 12).cwiseAbs();
    SparseMatrix A = K;
    Vector y;
    scale_shift_multiply(K, 0.3, d, x, A, y);
    SparseMatrix expected = 0.3 * K;
    expected.diagonal() += d;
    EXPECT_LE((A - expected).norm(), 1e-14 * expected.norm());
    EXPECT_EQ(A.nonZeros(), K.nonZeros());
    EXPECT_LE((y - K * x).norm(), 1e-13 * (K * x).norm());
}
