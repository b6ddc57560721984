// The AMG cycle on several threads (amg_cycle.hpp): l1 hybrid Gauss-Seidel on the finest level
// and on the large coarse levels keeps the cycle symmetric positive definite, converges like the
// serial cycle, and repeats bit for bit for a given thread count.
#include "amg_box.hpp"
#include "grid_matrix.hpp"
#include "polycut/solve/pcg.hpp"

#include <algorithm>
#include <cstring>
#include <gtest/gtest.h>
#include <numeric>
#include <random>
#include <string>
#include <vector>

using namespace polycut;
using namespace polycut::solve;
using polycut::solve::testing::amg_options;
using polycut::solve::testing::box_system;
using polycut::solve::testing::BoxSystem;
using polycut::solve::testing::random_vector;

TEST(Amg, TwoThreadsConvergeLikeOneAndRepeatBitForBit) {
    // Hybrid Gauss-Seidel on the finest level (two row blocks, Jacobi across) keeps the cycle
    // symmetric: PCG converges to the same tolerance in about the same count (a 12^3 box in grid
    // order: one layer of nodes couples the blocks); the same thread count repeats exactly, and
    // the threaded SpMV equals the serial one bit for bit.
    const BoxSystem s = box_system(12);
    const double h = 0.01, beta = 0.01;
    SparseMatrix A = (h * h + h * beta) * s.K;
    A.diagonal() += s.mass;
    const Vector b = random_vector(A.rows(), 11);
    PcgOptions o = amg_options(1e-8);
    o.refactor_iterations = 1000;
    PcgSolver serial(o);
    Vector x1;
    const PcgResult r1 = serial.solve(A, b, x1);
    ASSERT_EQ(r1.status, SolveStatus::Ok);
    o.threads = 2;
    PcgSolver two(o), again(o);
    Vector x2, x3;
    const PcgResult r2 = two.solve(A, b, x2);
    ASSERT_EQ(r2.status, SolveStatus::Ok);
    EXPECT_LE(r2.iterations, r1.iterations + 2);
    EXPECT_LE(Vector(A * x2 - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
    EXPECT_LE((x2 - x1).norm(), 1e-6 * x1.norm());
    ASSERT_EQ(again.solve(A, b, x3).status, SolveStatus::Ok);
    EXPECT_EQ(std::memcmp(x2.data(), x3.data(), sizeof(double) * std::size_t(x2.size())), 0);
    Vector y1, y2;
    multiply_symmetric(A, b, y1);
    multiply_symmetric(A, b, y2, 2);
    EXPECT_EQ(std::memcmp(y1.data(), y2.data(), sizeof(double) * std::size_t(y1.size())), 0);
}

TEST(Amg, CoarseLevelsSmoothOnTwoThreadsAndTheCycleStaysSymmetricPositiveDefinite) {
    // A coarse level of at least 20,000 entries is smoothed by l1 hybrid Gauss-Seidel like the
    // finest (amg_cycle.hpp): a 14^3 box (9,000 unknowns) has such a level. A non-symmetric or
    // indefinite cycle would stall PCG above 1e-10 or break down; the threaded cycle converges
    // to it in at most a few iterations more than the serial one (its coarse smoothing is
    // weaker), to the same solution, and repeats bit for bit.
    const BoxSystem s = box_system(14);
    const double h = 1.0 / 60, beta = 0.01;
    SparseMatrix A = (h * h + h * beta) * s.K;
    A.diagonal() += s.mass;
    const Vector b = random_vector(A.rows(), 17);
    PcgOptions o = amg_options(1e-10);
    o.refactor_iterations = 1000;
    PcgSolver serial(o);
    Vector x1;
    const PcgResult r1 = serial.solve(A, b, x1);
    ASSERT_EQ(r1.status, SolveStatus::Ok);
    EXPECT_EQ(serial.amg_threaded_levels(), 0);
    o.threads = 2;
    PcgSolver two(o), again(o);
    Vector x2, x3;
    const PcgResult r2 = two.solve(A, b, x2);
    ASSERT_EQ(r2.status, SolveStatus::Ok) << to_string(r2.status);
    EXPECT_GE(two.amg_threaded_levels(), 2); // the finest and at least one coarse level
    EXPECT_LE(r2.iterations, r1.iterations + 4);
    EXPECT_LE(Vector(A * x2 - b).norm(), 1e-10 * b.norm() * (1 + 1e-6));
    EXPECT_LE((x2 - x1).norm(), 1e-8 * x1.norm());
    ASSERT_EQ(again.solve(A, b, x3).status, SolveStatus::Ok);
    EXPECT_EQ(std::memcmp(x2.data(), x3.data(), sizeof(double) * std::size_t(x2.size())), 0);
    RecordProperty("iterations_one_two_threads",
        std::to_string(r1.iterations) + " " + std::to_string(r2.iterations) + " levels "
            + std::to_string(two.amg_levels()) + " threaded "
            + std::to_string(two.amg_threaded_levels()));
}

TEST(Amg, TwoThreadsStayPositiveDefiniteWhenEveryRowCrossesBlocks) {
    // The worst case for the two-block smoother: nodes numbered at random, so half of every
    // row's entries lie in the other block. Plain hybrid Gauss-Seidel is then close to Jacobi
    // across blocks, which does not converge for this nearly incompressible stiffness (the
    // V-cycle stops being positive definite and PCG breaks down, as after cuts on the organ);
    // the l1 variant stays convergent: PCG reaches the tolerance, if in more iterations.
    const BoxSystem s = box_system(8);
    SparseMatrix A = 1e-2 * s.K;
    A.diagonal() += s.mass;
    const long nodes = A.rows() / 3;
    std::vector<int> order(static_cast<std::size_t>(nodes));
    std::iota(order.begin(), order.end(), 0);
    std::mt19937 rng(3);
    std::shuffle(order.begin(), order.end(), rng);
    Eigen::VectorXi perm(A.rows());
    for (long i = 0; i < nodes; ++i)
        for (int c = 0; c < 3; ++c)
            perm[3 * i + c] = 3 * order[static_cast<std::size_t>(i)] + c;
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(perm);
    SparseMatrix B(A.rows(), A.cols());
    B = A.twistedBy(P);
    B.makeCompressed();
    const Vector b = random_vector(B.rows(), 13);
    PcgOptions o = amg_options(1e-8);
    o.refactor_iterations = 1000;
    o.threads = 2;
    PcgSolver pcg(o);
    Vector x;
    const PcgResult r = pcg.solve(B, b, x);
    EXPECT_EQ(r.status, SolveStatus::Ok) << to_string(r.status);
    EXPECT_LE(Vector(B * x - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
}

TEST(Amg, ThreadedCycleConvergesWhereHybridSmoothingDoesNot) {
    // A = [[K, bK], [bK, K]] with K = tridiag(-1, 2.01, -1) and b = 0.99 is SPD (eigenvalues
    // (1 +- b) eig(K) > 0), but hybrid Gauss-Seidel with the two thread blocks = the two halves
    // converges only if b ||D^-1/2 K D^-1/2|| < 1 (b < ~0.5 here). The threaded solve (l1 hybrid
    // Gauss-Seidel on the finest level) must still reach the tolerance.
    const int m = 300;
    std::vector<Eigen::Triplet<double>> t;
    for (int half = 0; half < 2; ++half)
        for (int i = 0; i < m; ++i) {
            for (int other = 0; other < 2; ++other) {
                const double w = half == other ? 1.0 : 0.99;
                const int r = half * m + i, c = other * m + i;
                t.emplace_back(r, c, 2.01 * w);
                if (i > 0)
                    t.emplace_back(r, c - 1, -w);
                if (i + 1 < m)
                    t.emplace_back(r, c + 1, -w);
            }
        }
    SparseMatrix A(2 * m, 2 * m);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    const Vector b = random_vector(A.rows(), 5);
    PcgOptions o = amg_options(1e-8);
    o.refactor_iterations = 1000;
    o.max_iterations = 2000;
    o.threads = 2;
    PcgSolver two(o);
    Vector x;
    const PcgResult r = two.solve(A, b, x);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_LE(Vector(A * x - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
}
