// The AMG cycle's 3x3 node-block smoothing (AmgOptions::node_blocks, amg_cycle.hpp "Node
// blocks"): convergence against point smoothing on one and two threads, and the fall-back to point
// sweeps when the unknowns are not whole nodes.
#include "amg_box.hpp"
#include "grid_matrix.hpp"

#include <algorithm>
#include <cstring>
#include <gtest/gtest.h>
#include <string>
#include <vector>

using namespace polycut;
using namespace polycut::solve;
using polycut::solve::testing::amg_options;
using polycut::solve::testing::box_system;
using polycut::solve::testing::BoxSystem;
using polycut::solve::testing::random_vector;

TEST(Amg, NodeBlockSmoothingConvergesLikePointSmoothingOnOneAndTwoThreads) {
    // The finest level smoothed by 3x3 node blocks (AmgOptions::node_blocks, amg_cycle.hpp) is
    // still a symmetric positive definite cycle: PCG reaches 1e-8 (a non-symmetric or indefinite
    // cycle stalls or breaks down) in no more iterations than point Gauss-Seidel, + 1 for
    // round-off, on one and two threads; a new matrix of the same pattern (stiffness part 1.5x)
    // refreshes the block copy (its solve meets the tolerance on the new matrix).
    const BoxSystem s = box_system(10);
    const double h = 0.01, beta = 0.01;
    SparseMatrix A = (h * h + h * beta) * s.K;
    A.diagonal() += s.mass;
    SparseMatrix A2 = (1.5 * (h * h + h * beta)) * s.K;
    A2.diagonal() += s.mass;
    const Vector b = random_vector(A.rows(), 17);
    for (int threads : { 1, 2 }) {
        int its[2][2] = {};
        for (int blocks = 0; blocks < 2; ++blocks) {
            PcgOptions o = amg_options(1e-8);
            o.threads = threads;
            o.amg.node_blocks = blocks == 1;
            o.refactor_iterations = 1000;
            PcgSolver pcg(o);
            for (int m = 0; m < 2; ++m) {
                const SparseMatrix& M = m == 0 ? A : A2;
                Vector x;
                const PcgResult r = pcg.solve(M, b, x);
                ASSERT_EQ(r.status, SolveStatus::Ok) << threads << " " << blocks;
                EXPECT_LE(Vector(M * x - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
                its[blocks][m] = r.iterations;
            }
        }
        EXPECT_LE(its[1][0], its[0][0] + 1) << threads;
        EXPECT_LE(its[1][1], its[0][1] + 1) << threads;
        RecordProperty("amg_its_point_block_t" + std::to_string(threads),
            std::to_string(its[0][0]) + " " + std::to_string(its[1][0]) + " "
                + std::to_string(its[0][1]) + " " + std::to_string(its[1][1]));
    }
}

TEST(Amg, NodeBlocksFallBackToPointSweepsWhenNodesArePartlyFixed) {
    // Three DOFs of three different nodes removed (x of one, y of another, z of a third, as
    // single-component supports do): the size is still a multiple of 3 but the unknowns no
    // longer come as whole nodes, so the cycle keeps point Gauss-Seidel; with node_blocks on or
    // off the solves are then the same bit for bit.
    const BoxSystem s = box_system(6);
    SparseMatrix A = 1e-2 * s.K;
    A.diagonal() += s.mass;
    const long n = A.rows();
    const long k = n / 12;
    const std::vector<long> drop = { 3 * k, 3 * (2 * k) + 1, 3 * (3 * k) + 2 };
    std::vector<long> new_of(std::size_t(n), -1);
    long m = 0;
    for (long i = 0; i < n; ++i)
        if (std::find(drop.begin(), drop.end(), i) == drop.end())
            new_of[std::size_t(i)] = m++;
    ASSERT_EQ(m % 3, 0);
    std::vector<Eigen::Triplet<double>> t;
    for (long j = 0; j < n; ++j)
        for (SparseMatrix::InnerIterator it(A, j); it; ++it)
            if (new_of[std::size_t(it.row())] >= 0 && new_of[std::size_t(j)] >= 0)
                t.emplace_back(
                    int(new_of[std::size_t(it.row())]), int(new_of[std::size_t(j)]), it.value());
    SparseMatrix B(m, m);
    B.setFromTriplets(t.begin(), t.end());
    B.makeCompressed();
    const Vector b = random_vector(B.rows(), 19);
    Vector x[2];
    for (int blocks = 0; blocks < 2; ++blocks) {
        PcgOptions o = amg_options(1e-8);
        o.amg.node_blocks = blocks == 1;
        PcgSolver pcg(o);
        ASSERT_EQ(pcg.solve(B, b, x[blocks]).status, SolveStatus::Ok);
        EXPECT_LE(Vector(B * x[blocks] - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
    }
    EXPECT_EQ(std::memcmp(x[0].data(), x[1].data(), sizeof(double) * std::size_t(x[0].size())), 0);
}
