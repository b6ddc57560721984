// The DG elasticity operator (issue 13 item 1, 8): coercivity of IP with the default penalty on
// hex, prism, tet, jittered, cut, sliver and non-convex meshes (smallest eigenvalue and CHOLMOD
// LL^T), indefiniteness below a threshold, BZ positive for any penalty, rigid modes in the kernel,
// and the linear patch test (IP exact to round-off; BZ's error reported).
#include "dg_meshes.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/dg/polyhedron_moments.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/solve/cholmod_solver.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <random>

using namespace polycut;
using namespace polycut::dg;
using test::Kind;

namespace {
elasticity::Material material(double nu = 0.3) {
    elasticity::Material m;
    m.youngs_modulus = 1e4;
    m.poisson_ratio = nu;
    return m;
}

/// Smallest and largest eigenvalue of the dense K.
std::pair<double, double> extreme_eigenvalues(const solve::SparseMatrix& K) {
    const MatX dense(K);
    Eigen::SelfAdjointEigenSolver<MatX> eig(dense, Eigen::EigenvaluesOnly);
    return { eig.eigenvalues().minCoeff(), eig.eigenvalues().maxCoeff() };
}

double polygon_area_of(const mesh::Mesh& m, Index f) {
    double area = 0;
    polygon_normal(m.rest, m.faces[std::size_t(f)].nodes, &area);
    return area;
}

solve::SolveStatus cholesky(const solve::SparseMatrix& K) {
    solve::CholmodSolver chol;
    return chol.factorize(K);
}
} // namespace

TEST(DgOperator, InteriorPenaltyIsCoerciveOnEveryCellKind) {
    for (Kind kind : { Kind::Hex, Kind::Prism, Kind::Tet, Kind::JitteredTet, Kind::Cut,
             Kind::Sliver, Kind::NonConvex })
        for (int p : { 1, 2 }) {
            const mesh::Mesh m = test::box_mesh(kind, 2);
            DgOptions o;
            o.degree = p;
            const DgModel model(m, material(), o, test::faces_on_plane(m, 0, 0.0));
            const solve::SparseMatrix K = model.stiffness();
            const auto [lo, hi] = extreme_eigenvalues(K);
            EXPECT_GT(lo, 0) << test::name(kind) << " p=" << p << " (" << m.num_cells()
                             << " cells)";
            EXPECT_EQ(cholesky(K), solve::SolveStatus::Ok) << test::name(kind) << " p=" << p;
            std::cout << test::name(kind) << " p=" << p << " cells " << m.num_cells()
                      << " lambda_min/lambda_max " << lo / hi << "\n";
        }
}

TEST(DgOperator, InteriorPenaltyBelowThresholdIsIndefiniteAndCholeskySaysSo) {
    const mesh::Mesh m = test::box_mesh(Kind::Hex, 2);
    DgOptions o;
    o.penalty = 0.05;
    o.dirichlet_penalty = 0.05;
    const DgModel ip(m, material(), o, test::faces_on_plane(m, 0, 0.0));
    EXPECT_LT(extreme_eigenvalues(ip.stiffness()).first, 0);
    EXPECT_EQ(cholesky(ip.stiffness()), solve::SolveStatus::NotPositiveDefinite);
    // BZ is positive definite for any penalty (003 sec. 4).
    o.flux = Flux::BabuskaZlamal;
    const DgModel bz(m, material(), o, test::faces_on_plane(m, 0, 0.0));
    EXPECT_GT(extreme_eigenvalues(bz.stiffness()).first, 0);
}

TEST(DgOperator, RigidMotionsAreInTheKernelAndSymmetric) {
    for (Kind kind : { Kind::Hex, Kind::Tet, Kind::Cut, Kind::NonConvex })
        for (int p : { 1, 2 }) {
            const mesh::Mesh m = test::box_mesh(kind, 2);
            DgOptions o;
            o.degree = p;
            const DgModel model(m, material(), o);
            const solve::SparseMatrix K = model.stiffness();
            EXPECT_LT((MatX(K) - MatX(K).transpose()).norm(), 1e-12 * MatX(K).norm());
            const Vec3 w(0.3, -0.2, 0.5), t(1, 2, 3);
            MatX3 U(model.num_coefficients(), 3);
            for (Index r = 0; r < U.rows(); ++r)
                U.row(r) = w.cross(Vec3(model.rest().row(r))).transpose();
            for (Index c = 0; c < model.num_cells(); ++c)
                U.row(model.offset(c)) += t.transpose();
            const VecX f = K * flat(U);
            EXPECT_LT(f.norm(), 1e-10 * MatX(K).norm() * flat(U).norm()) << test::name(kind);
        }
}

namespace {
/// Max error of the patch test (all boundary faces Dirichlet with an affine g) over the
/// coefficients, relative to |G|.
double patch_error_on(const mesh::Mesh& m, int p, Flux flux);

double patch_error(Kind kind, int p, Flux flux) {
    return patch_error_on(test::box_mesh(kind, 2), p, flux);
}

double patch_error_on(const mesh::Mesh& m, int p, Flux flux) {
    DgOptions o;
    o.degree = p;
    o.flux = flux;
    const DgModel model(m, material(), o, test::all_boundary_faces(m));
    const Vec3 g0(1e-3, -2e-3, 0.5e-3);
    Mat3 G;
    G << 1e-2, 2e-3, -3e-3, 0.5e-2, -1e-2, 4e-3, 2e-3, 1e-3, 0.7e-2;
    const VecX F = model.dirichlet_load(g0, G);
    const solve::SparseMatrix K = model.stiffness();
    solve::CholmodSolver chol;
    EXPECT_EQ(chol.factorize(K), solve::SolveStatus::Ok);
    VecX U;
    chol.solve(F, U);
    // One step of iterative refinement (the DG matrix's condition number scales round-off).
    VecX dU;
    chol.solve(F - K * U, dU);
    U += dU;
    MatX3 exact(model.num_coefficients(), 3);
    for (Index r = 0; r < exact.rows(); ++r)
        exact.row(r) = (G * Vec3(model.rest().row(r))).transpose();
    for (Index c = 0; c < model.num_cells(); ++c)
        exact.row(model.offset(c)) += g0.transpose();
    return (U - flat(exact)).lpNorm<Eigen::Infinity>() / G.norm();
}
} // namespace

TEST(DgOperator, LinearPatchTestInteriorPenaltyExact) {
    for (Kind kind :
        { Kind::Hex, Kind::Prism, Kind::Tet, Kind::JitteredTet, Kind::Cut, Kind::NonConvex })
        for (int p : { 1, 2 }) {
            const double e = patch_error(kind, p, Flux::InteriorPenalty);
            EXPECT_LT(e, 1e-12) << test::name(kind) << " p=" << p;
        }
}

TEST(DgOperator, LinearPatchTestOnNonPlanarFacesExact) {
    // Hexes of a 3^3 grid whose interior nodes are moved by up to 0.15 h: every interior face
    // is a non-planar quad (cut meshes with snapped nodes have such faces). Each face is
    // integrated as the triangles around its mean point, the same for both cells, so the
    // cells are the polyhedra those triangles bound and IP stays exact.
    mesh::BoxGrid g;
    g.cells = Eigen::Vector3i(3, 3, 3);
    mesh::Mesh m = mesh::hex_grid(g);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.15, 0.15);
    double bend = 0;
    for (Vec3& X : m.rest)
        if ((X.array() > 1e-12).all() && (X.array() < 1 - 1e-12).all())
            for (int a = 0; a < 3; ++a)
                X[a] += u(rng) / 3.0;
    for (const mesh::Face& f : m.faces) {
        const auto& n = f.nodes;
        const Vec3 normal = (m.rest[std::size_t(n[2])] - m.rest[std::size_t(n[0])])
                                .cross(m.rest[std::size_t(n[3])] - m.rest[std::size_t(n[1])])
                                .normalized();
        for (Index v : n)
            bend = std::max(
                bend, std::abs((m.rest[std::size_t(v)] - m.rest[std::size_t(n[0])]).dot(normal)));
    }
    EXPECT_GT(bend, 1e-3); // the faces really are warped
    for (int p : { 1, 2 }) {
        const double e = patch_error_on(m, p, Flux::InteriorPenalty);
        std::cout << "non-planar faces (warp " << bend << " m) p=" << p << ": patch error " << e
                  << "\n";
        EXPECT_LT(e, 1e-11) << "p=" << p;
    }
}

TEST(DgOperator, LinearPatchTestBabuskaZlamalErrorReported) {
    // BZ is not consistent (003 sec. 4): the affine field is not its solution. Its error is
    // reported (docs/decisions/0020) and must be visible but bounded.
    for (int p : { 1, 2 }) {
        const double e = patch_error(Kind::Hex, p, Flux::BabuskaZlamal);
        std::cout << "BZ patch error p=" << p << ": " << e << " (relative to |G|)\n";
        RecordProperty("bz_patch_error_p" + std::to_string(p), std::to_string(e));
        EXPECT_GT(e, 1e-6);
        EXPECT_LT(e, 1.0);
    }
}

TEST(DgOperator, TestMeshesCoverTheUnitCube) {
    for (Kind kind : { Kind::Hex, Kind::Prism, Kind::Tet, Kind::Cut, Kind::NonConvex }) {
        const mesh::Mesh m = test::box_mesh(kind, 3);
        EXPECT_NEAR(m.rest_volume(), 1.0, 1e-12) << test::name(kind);
        double area = 0;
        for (Index f : m.boundary_faces()) {
            area += polygon_area_of(m, f);
            Vec3 c = Vec3::Zero();
            for (Index v : m.faces[std::size_t(f)].nodes)
                c += m.rest[std::size_t(v)] / double(m.faces[std::size_t(f)].nodes.size());
            const bool outer = (c.array() < 1e-12).any() || (c.array() > 1 - 1e-12).any();
            EXPECT_TRUE(outer) << test::name(kind) << " boundary face " << f << " at "
                               << c.transpose() << " with " << m.faces[std::size_t(f)].nodes.size()
                               << " nodes";
        }
        EXPECT_NEAR(area, 6.0, 1e-12) << test::name(kind);
    }
}
