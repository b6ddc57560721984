// The AMG hierarchy carried over a cut (docs/decisions/0009, 0017): the unknowns renumbered
// and new ones appended, PCG preconditioned by the remapped hierarchy without a new set-up, and
// the new unknowns interpolating from their origins.
#include "amg_box.hpp"
#include "grid_matrix.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/solve/pcg.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <vector>

using namespace polycut;
using namespace polycut::solve;
using polycut::solve::testing::amg_options;
using polycut::solve::testing::box_system;
using polycut::solve::testing::BoxSystem;
using polycut::solve::testing::random_vector;

namespace {
/// M + (h^2 + h beta) K of a box system, h = 0.01 s, beta = 0.01 s.
SparseMatrix step_matrix(const BoxSystem& s) {
    const double h = 0.01, beta = 0.01;
    SparseMatrix A = (h * h + h * beta) * s.K;
    A.diagonal() += s.mass;
    return A;
}

/// AMG PCG at 1e-8 whose hierarchy is only set up once (carried over the remaps).
PcgOptions carried_options() {
    PcgOptions o = amg_options(1e-8);
    o.refactor_iterations = 1000;
    return o;
}
} // namespace

TEST(Amg, HierarchyCarriedOverARenumberingSolvesWithoutASetUp) {
    // What a cut does to the step matrix: unknowns renumbered (here the last node's three rows
    // move to the front) and new ones appended (three rows coupled to the first node). The
    // remapped hierarchy (zero interpolation rows for the new unknowns) must still precondition
    // PCG to the tolerance without a new set-up.
    const SparseMatrix A = step_matrix(box_system(8));
    const long n = A.rows();
    PcgSolver pcg(carried_options());
    Vector x;
    ASSERT_EQ(pcg.solve(A, random_vector(n, 3), x).status, SolveStatus::Ok);
    ASSERT_EQ(pcg.refactorizations(), 1);
    // new row r <- old row old_of[r]
    std::vector<long> old_of;
    for (long i = n - 3; i < n; ++i)
        old_of.push_back(i);
    for (long i = 0; i < n - 3; ++i)
        old_of.push_back(i);
    for (int k = 0; k < 3; ++k)
        old_of.push_back(-1);
    const long m = long(old_of.size());
    std::vector<long> new_of(static_cast<std::size_t>(n), 0);
    for (long r = 0; r < m; ++r)
        if (old_of[std::size_t(r)] >= 0)
            new_of[std::size_t(old_of[std::size_t(r)])] = r;
    std::vector<Eigen::Triplet<double>> t;
    for (int c = 0; c < A.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(A, c); it; ++it)
            t.emplace_back(
                int(new_of[std::size_t(it.row())]), int(new_of[std::size_t(c)]), it.value());
    const double a00 = A.coeff(0, 0);
    for (int k = 0; k < 3; ++k) {
        const int r = int(n) + k, first = int(new_of[std::size_t(k)]);
        t.emplace_back(r, r, a00);
        t.emplace_back(r, first, -0.3 * a00);
        t.emplace_back(first, r, -0.3 * a00);
        t.emplace_back(first, first, 0.3 * a00); // keeps the row diagonally dominant
    }
    SparseMatrix B(m, m);
    B.setFromTriplets(t.begin(), t.end());
    B.makeCompressed();
    ASSERT_TRUE(pcg.remap_preconditioner(RowRemap { old_of, {}, {}, {} }));
    const Vector b = random_vector(m, 4);
    Vector y;
    const PcgResult r = pcg.solve(B, b, y);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_FALSE(r.refactored);
    EXPECT_EQ(pcg.refactorizations(), 1);
    EXPECT_LE(Vector(B * y - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
    // 27 iterations; the same hierarchy with its rows left at their old numbers needs 37
    EXPECT_LE(r.iterations, 30);
}

namespace {
/// Step matrix (M + (h^2 + h beta) K, h = 1/60 s, beta = 0.01) of a Kuhn box of side 0.1 m with
/// x = 0 fixed; with `cut`, the box is cut along the grid plane x = 0.05 m below z = 0.05 m
/// (the cells right of the plane take copies of its nodes, appended after the original nodes:
/// what a face-conforming cut does).
SparseMatrix box_step_matrix(int n, bool cut) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    const mesh::Mesh box = mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
    std::vector<Vec3> rest = box.rest;
    std::vector<std::array<Index, 4>> tets;
    std::vector<Index> copy(rest.size(), kNone);
    for (const mesh::Cell& c : box.cells) {
        std::array<Index, 4> t {};
        Vec3 centre = Vec3::Zero();
        for (int k = 0; k < 4; ++k) {
            t[std::size_t(k)] = c.nodes[std::size_t(k)];
            centre += rest[std::size_t(c.nodes[std::size_t(k)])] / 4;
        }
        if (cut && centre.x() > 0.05)
            for (Index& v : t) {
                const Vec3 p = box.rest[std::size_t(v)];
                if (std::abs(p.x() - 0.05) < 1e-9 && p.z() < 0.05 - 1e-9) {
                    if (copy[std::size_t(v)] == kNone) {
                        copy[std::size_t(v)] = Index(rest.size());
                        rest.push_back(p);
                    }
                    v = copy[std::size_t(v)];
                }
            }
        tets.push_back(t);
    }
    const mesh::Mesh m = mesh::Mesh::from_tets(rest, tets);
    std::vector<std::uint8_t> fixed(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        fixed[std::size_t(i)] = std::abs(m.rest[std::size_t(i)].x()) < 1e-9;
    elasticity::Material material;
    material.youngs_modulus = 1e4;
    material.poisson_ratio = 0.45;
    material.density = 1000;
    elasticity::ElasticModel model(
        m, material, basis::BasisOptions {}, elasticity::fix_nodes(fixed));
    SparseMatrix K = model.make_matrix();
    VecX f;
    MatX3 x(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        x.row(i) = m.rest[std::size_t(i)].transpose();
    model.assemble(x, elasticity::ForceMode::Linear, &K, &f);
    const double h = 1.0 / 60, beta = 0.01;
    SparseMatrix A = (h * h + h * beta) * K;
    A.diagonal() += model.reduced_mass();
    A.makeCompressed();
    return A;
}
} // namespace

TEST(Amg, NewUnknownsInterpolateFromTheirOrigins) {
    // A cut along a grid plane duplicates the plane's nodes. The hierarchy of the uncut box is
    // carried over (the old unknowns keep their numbers: free nodes before the cut are numbered
    // first); the copies' rows either stay zero (no coarse correction for them) or take their
    // origins' rows, as the integrator gives them (the same axis of the uncut neighbours; here
    // the node they copy). Both must converge without a set-up; the origins must need clearly
    // fewer iterations (to 1e-4: 26 with zero rows, 22 with origins).
    const int n = 8;
    const SparseMatrix A = box_step_matrix(n, false);
    const SparseMatrix B = box_step_matrix(n, true);
    const long rows = A.rows(), m = B.rows();
    ASSERT_GT(m, rows); // the cut added unknowns
    RowRemap plain;
    for (long i = 0; i < m; ++i)
        plain.old_of.push_back(i < rows ? i : -1);
    RowRemap with_origins = plain;
    with_origins.origin_ptr.assign(std::size_t(m) + 1, 0);
    {
        // the DOFs of the uncut box's plane nodes below z = 0.05, in node order, and of the
        // copies, appended in the order the copies were made (also node order)
        mesh::BoxGrid g;
        g.lo = Vec3::Zero();
        g.hi = Vec3::Constant(0.1);
        g.cells = Eigen::Vector3i(n, n, n);
        const mesh::Mesh box = mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
        std::vector<long> free_dof(box.rest.size(), -1);
        long next = 0;
        for (std::size_t i = 0; i < box.rest.size(); ++i)
            if (std::abs(box.rest[i].x()) >= 1e-9)
                free_dof[i] = next++ * 3;
        ASSERT_EQ(next * 3, rows);
        // copies were made in the order of first use by a cell; origins by rest position
        std::vector<long> plane;
        for (const mesh::Cell& c : box.cells) {
            Vec3 centre = Vec3::Zero();
            for (Index v : c.nodes)
                centre += box.rest[std::size_t(v)] / 4;
            if (centre.x() <= 0.05)
                continue;
            for (Index v : c.nodes) {
                const Vec3 p = box.rest[std::size_t(v)];
                if (std::abs(p.x() - 0.05) < 1e-9 && p.z() < 0.05 - 1e-9
                    && std::find(plane.begin(), plane.end(), long(v)) == plane.end())
                    plane.push_back(long(v));
            }
        }
        ASSERT_EQ(long(plane.size()) * 3, m - rows);
        for (long r = 0; r < m; ++r) {
            if (r >= rows) {
                const long node = plane[std::size_t((r - rows) / 3)];
                with_origins.origin_row.push_back(free_dof[std::size_t(node)] + (r - rows) % 3);
                with_origins.origin_weight.push_back(1.0);
            }
            with_origins.origin_ptr[std::size_t(r) + 1] = int(with_origins.origin_row.size());
        }
    }
    int iterations[2] = { 0, 0 };
    for (int variant = 0; variant < 2; ++variant) {
        PcgOptions o = amg_options(1e-4);
        o.refactor_iterations = 1000;
        PcgSolver pcg(o);
        Vector x;
        ASSERT_EQ(pcg.solve(A, random_vector(rows, 3), x).status, SolveStatus::Ok);
        ASSERT_TRUE(pcg.remap_preconditioner(variant == 0 ? plain : with_origins));
        const Vector b = random_vector(m, 4);
        Vector y;
        const PcgResult r = pcg.solve(B, b, y);
        ASSERT_EQ(r.status, SolveStatus::Ok);
        EXPECT_FALSE(r.refactored);
        EXPECT_LE(Vector(B * y - b).norm(), 1e-4 * b.norm() * (1 + 1e-6));
        iterations[variant] = r.iterations;
    }
    EXPECT_LT(double(iterations[1]), 0.9 * double(iterations[0]))
        << "zero rows " << iterations[0] << ", origins " << iterations[1];
}

TEST(Amg, KeptSolutionsFollowACutAndProjectWithTheNewMatrix) {
    // PcgOptions::start_vectors with a carried hierarchy: remap_preconditioner() moves the kept
    // solutions to the new unknowns (a new one takes its origin's value) and the next solve
    // starts from their Galerkin projection with the new matrix B (products recomputed): its
    // start residual is the one of x0 = V c, V^T B V c = V^T b, computed here densely (1e-8).
    const SparseMatrix A = step_matrix(box_system(6));
    const long n = A.rows();
    PcgOptions o = carried_options();
    o.start_vectors = 3;
    PcgSolver pcg(o);
    Vector x;
    std::vector<Vector> kept;
    for (unsigned k = 0; k < 3; ++k) {
        ASSERT_EQ(pcg.solve(A, random_vector(n, 20 + k), x).status, SolveStatus::Ok);
        kept.push_back(x);
    }
    // Three new unknowns appended, coupled to (and originating from) rows 0, 1, 2.
    std::vector<long> old_of(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i)
        old_of[std::size_t(i)] = i;
    RowRemap remap { old_of, {}, {}, {} };
    remap.origin_ptr.assign(std::size_t(n) + 1, 0);
    std::vector<Eigen::Triplet<double>> t;
    for (int c = 0; c < A.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(A, c); it; ++it)
            t.emplace_back(int(it.row()), c, it.value());
    const double a00 = A.coeff(0, 0);
    for (int k = 0; k < 3; ++k) {
        remap.old_of.push_back(-1);
        remap.origin_row.push_back(k);
        remap.origin_weight.push_back(1.0);
        remap.origin_ptr.push_back(k + 1);
        const int r = int(n) + k;
        t.emplace_back(r, r, a00);
        t.emplace_back(r, k, -0.3 * a00);
        t.emplace_back(k, r, -0.3 * a00);
        t.emplace_back(k, k, 0.3 * a00);
    }
    const long m = n + 3;
    SparseMatrix B(m, m);
    B.setFromTriplets(t.begin(), t.end());
    B.makeCompressed();
    ASSERT_TRUE(pcg.remap_preconditioner(remap));

    Eigen::MatrixXd V(m, 3);
    for (int i = 0; i < 3; ++i) {
        V.col(i).head(n) = kept[std::size_t(i)];
        V.col(i).tail(3) = kept[std::size_t(i)].head(3);
    }
    const Vector b = random_vector(m, 30);
    const Eigen::VectorXd c = (V.transpose() * (B * V)).ldlt().solve(V.transpose() * b);
    const Vector x0 = V * c;
    const double expected = Vector(b - B * x0).norm() / b.norm();
    Vector y = Vector::Zero(m);
    const PcgResult r = pcg.solve(B, b, y);
    ASSERT_EQ(r.status, SolveStatus::Ok);
    EXPECT_NEAR(r.start_residual, expected, 1e-8 * expected);
    EXPECT_LE(Vector(B * y - b).norm(), 1e-8 * b.norm() * (1 + 1e-6));
}
