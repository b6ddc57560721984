// The two-level DG preconditioner (docs/decisions/0024): the coarse space carries a global
// affine field to its exact DG coefficients on every cell kind; the preconditioner is
// symmetric and positive definite (also with a lagged coarse level); PCG with it reaches the
// CHOLMOD solution of an implicit Euler system and needs far fewer iterations than the cell
// block Jacobi it smooths with.
#include "dg_meshes.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <gtest/gtest.h>
#include <random>

using namespace polycut;
using namespace polycut::dg;
using test::Kind;

namespace {

/// Node coordinates in the coarse space's column order (nodes some cell uses, first use).
VecX used_node_field(const mesh::Mesh& m, const Mat3& G, const Vec3& g0) {
    std::vector<Index> column(std::size_t(m.num_nodes()), kNone);
    std::vector<Index> order;
    for (const mesh::Cell& cell : m.cells)
        for (Index n : cell.nodes)
            if (column[std::size_t(n)] == kNone) {
                column[std::size_t(n)] = Index(order.size());
                order.push_back(n);
            }
    VecX u(3 * Index(order.size()));
    for (std::size_t k = 0; k < order.size(); ++k)
        u.segment<3>(3 * Index(k)) = g0 + G * m.rest[std::size_t(order[k])];
    return u;
}

/// The implicit Euler matrix M + h^2 K of a DG model (dt = 10 ms).
solve::SparseMatrix system_matrix(const DgModel& model) {
    solve::SparseMatrix A = model.stiffness() * 1e-4;
    for (Index k = 0; k < A.rows(); ++k)
        A.coeffRef(int(k), int(k)) += model.reduced_mass()[k];
    A.makeCompressed();
    return A;
}

std::vector<Index> left_faces(const mesh::Mesh& m) {
    return test::faces_on_plane(m, 0, 0.0);
}
} // namespace

TEST(DgTwoLevel, CoarseSpaceCarriesAnAffineFieldExactlyOnEveryCellKind) {
    // u = g0 + G X on the nodes -> the cells' coefficients of that field (X0 maps to the rest
    // coefficients): exact for the P1 fit on tets, hexes, cut and non-convex cells.
    const Mat3 G = (Mat3() << 0.1, -0.2, 0.05, 0.3, 0.02, -0.1, -0.07, 0.15, 0.2).finished();
    const Vec3 g0(0.01, -0.02, 0.03);
    for (Kind kind : { Kind::Tet, Kind::Hex, Kind::Prism, Kind::Cut, Kind::NonConvex }) {
        const mesh::Mesh m = test::box_mesh(kind, 3);
        DgOptions o;
        o.degree = kind == Kind::Hex ? 2 : 1;
        const DgModel model(m, test::tissue_material(), o, left_faces(m));
        const solve::SparseMatrix P = model.coarse_space();
        ASSERT_EQ(P.rows(), 3 * model.num_coefficients());
        const VecX coeffs = P * used_node_field(m, G, g0);
        // Expected: the coefficients of g0 + G x on each cell, G applied to the rest rows.
        double worst = 0;
        for (Index c = 0; c < model.num_cells(); ++c)
            for (int i = 0; i < model.basis(c).size(); ++i) {
                const Index r = model.offset(c) + i;
                Vec3 expected = G * model.rest().row(r).transpose();
                if (i == 0)
                    expected += g0;
                worst = std::max(worst, (coeffs.segment<3>(3 * r) - expected).norm());
            }
        EXPECT_LT(worst, 1e-13) << test::name(kind);
    }
}

TEST(DgTwoLevel, PreconditionedCgReachesTheCholeskySolutionWithFewIterations) {
    for (Kind kind : { Kind::Tet, Kind::JitteredTet, Kind::Hex }) {
        const mesh::Mesh m = test::box_mesh(kind, kind == Kind::Hex ? 5 : 3);
        const DgModel model(m, test::tissue_material(), DgOptions {}, left_faces(m));
        const solve::SparseMatrix A = system_matrix(model);
        VecX b = model.body_load(Vec3(0, 0, -9810));
        std::mt19937 rng(3);
        std::normal_distribution<double> noise(0, 1);
        for (Index k = 0; k < b.size(); ++k)
            b[k] += noise(rng); // not only the smooth load
        solve::CholmodSolver chol;
        ASSERT_EQ(chol.factorize(A), solve::SolveStatus::Ok);
        VecX exact;
        ASSERT_EQ(chol.solve(b, exact), solve::SolveStatus::Ok);

        auto run = [&](solve::Preconditioner pre) {
            solve::PcgOptions o;
            o.preconditioner = pre;
            o.relative_tolerance = 1e-10;
            solve::PcgSolver pcg(o);
            pcg.set_blocks(model.dof_blocks());
            pcg.set_coarse_space(model.coarse_space());
            VecX x;
            const solve::PcgResult r = pcg.solve(A, b, x);
            EXPECT_EQ(r.status, solve::SolveStatus::Ok) << test::name(kind);
            EXPECT_EQ(r.used, pre);
            EXPECT_LT((x - exact).norm(), 1e-8 * exact.norm()) << test::name(kind);
            return r.iterations;
        };
        const int two_level = run(solve::Preconditioner::TwoLevel);
        const int blocks = run(solve::Preconditioner::BlockJacobi);
        RecordProperty(test::name(kind) + "_two_level", two_level);
        RecordProperty(test::name(kind) + "_block_jacobi", blocks);
        // Measured 2026-12-02 at 1e-10 from zero: tet 43 vs 83 iterations (jittered tets and
        // hexes under half too); the bound asks for a third fewer.
        EXPECT_LT(3 * two_level, 2 * blocks)
            << test::name(kind) << ": " << two_level << " vs " << blocks;
    }
}

TEST(DgTwoLevel, PreconditionerIsSymmetricPositiveDefiniteAlsoWhenLagged) {
    // B from the rest matrix applied while A is a different (stiffer) matrix: PCG still
    // converges to 1e-12 (it needs B symmetric positive definite; an indefinite or
    // non-symmetric B stalls or breaks down).
    const mesh::Mesh m = test::box_mesh(Kind::Tet, 2);
    const DgModel model(m, test::tissue_material(), DgOptions {}, left_faces(m));
    const solve::SparseMatrix A0 = system_matrix(model);
    solve::PcgOptions o;
    o.preconditioner = solve::Preconditioner::TwoLevel;
    o.relative_tolerance = 1e-12;
    o.two_level_fresh_smoother = false; // smoother and coarse level both of A0
    solve::PcgSolver pcg(o);
    pcg.set_blocks(model.dof_blocks());
    pcg.set_coarse_space(model.coarse_space());
    VecX b = VecX::Ones(A0.rows()), x;
    ASSERT_EQ(pcg.solve(A0, b, x).status, solve::SolveStatus::Ok);
    const solve::SparseMatrix A1 = A0 + solve::SparseMatrix(model.stiffness() * 3e-4);
    x.setZero();
    const solve::PcgResult r = pcg.solve(A1, b, x);
    ASSERT_EQ(r.status, solve::SolveStatus::Ok);
    EXPECT_FALSE(r.refactored); // the coarse level of A0 carried the solve
    EXPECT_LT((A1 * x - b).norm(), 1e-10 * b.norm());
}
