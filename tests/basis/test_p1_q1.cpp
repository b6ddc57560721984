// P1 and Q1 shape functions: finite-difference gradients, partition of unity, linear
// reproduction, volumes, and the per-cell dispatch.
#include "polycut/basis/cell_basis.hpp"
#include "polycut/basis/p1.hpp"
#include "polycut/basis/q1.hpp"
#include "polycut/common/error.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>
#include <random>

using namespace polycut;
using namespace polycut::basis;

namespace {
std::array<Vec3, 4> some_tet() {
    return { Vec3(0.1, 0.0, 0.2), Vec3(1.2, 0.1, 0.0), Vec3(0.3, 0.9, 0.1), Vec3(0.2, 0.3, 1.0) };
}

std::array<Vec3, 8> distorted_hex() {
    std::array<Vec3, 8> X;
    const auto& R = q1_reference_nodes();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.15, 0.15);
    for (int i = 0; i < 8; ++i)
        X[std::size_t(i)]
            = Vec3(0.5 * (R(i, 0) + 1) * 2.0, 0.5 * (R(i, 1) + 1) * 1.0, 0.5 * (R(i, 2) + 1) * 1.5)
            + Vec3(jitter(rng), jitter(rng), jitter(rng));
    return X;
}
} // namespace

TEST(P1, GradientsMatchFiniteDifferences) {
    const auto X = some_tet();
    const auto G = p1_gradients(X);
    const Vec3 p(0.3, 0.25, 0.3);
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a) {
        Vec3 dp = Vec3::Zero();
        dp(a) = h;
        const Eigen::Vector4d fd = (p1_shape(X, p + dp) - p1_shape(X, p - dp)) / (2 * h);
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(fd(i), G(i, a), 1e-8);
    }
}

TEST(P1, PartitionOfUnityAndVertexInterpolation) {
    const auto X = some_tet();
    EXPECT_NEAR(p1_shape(X, Vec3(0.4, 0.2, 0.3)).sum(), 1.0, 1e-14);
    for (int i = 0; i < 4; ++i) {
        const Eigen::Vector4d N = p1_shape(X, X[std::size_t(i)]);
        for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(N(j), i == j ? 1.0 : 0.0, 1e-14);
    }
    const auto G = p1_gradients(X);
    EXPECT_LT(G.colwise().sum().norm(), 1e-13);
    // Linear reproduction: sum_i X_i grad phi_i^T = I.
    Mat3 I = Mat3::Zero();
    for (int i = 0; i < 4; ++i)
        I += X[std::size_t(i)] * G.row(i);
    EXPECT_LT((I - Mat3::Identity()).norm(), 1e-13);
}

TEST(P1, IntegrationVolumeAndInvertedTet) {
    auto X = some_tet();
    const CellIntegration ci = p1_integration(X);
    const double vol = (X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0])) / 6.0;
    ASSERT_EQ(ci.weights.size(), 1u);
    EXPECT_NEAR(ci.weights[0], vol, 1e-15);
    EXPECT_NEAR(ci.lumped_volume.sum(), vol, 1e-15);
    std::swap(X[1], X[2]);
    EXPECT_THROW(p1_integration(X), MeshError);
}

TEST(Q1, ReferenceGradientsMatchFiniteDifferences) {
    const Vec3 xi(0.3, -0.4, 0.7);
    const auto D = q1_reference_gradients(xi);
    const double h = 1e-6;
    for (int b = 0; b < 3; ++b) {
        Vec3 d = Vec3::Zero();
        d(b) = h;
        const Eigen::Matrix<double, 8, 1> fd = (q1_shape(xi + d) - q1_shape(xi - d)) / (2 * h);
        for (int i = 0; i < 8; ++i)
            EXPECT_NEAR(fd(i), D(i, b), 1e-9);
    }
}

TEST(Q1, PhysicalGradientsByChainRuleOnDistortedHex) {
    const auto X = distorted_hex();
    const CellIntegration ci = q1_integration(X, 2);
    ASSERT_EQ(ci.points.size(), 8u);
    const double h = 1e-6;
    // Each quadrature point: recover xi by Newton on the map, then compare physical gradients
    // with finite differences of N(xi(x)) along each axis (xi(x) again by Newton).
    auto invert = [&](const Vec3& p) {
        Vec3 xi = Vec3::Zero();
        for (int it = 0; it < 50; ++it) {
            Eigen::Matrix<double, 8, 3> P;
            for (int i = 0; i < 8; ++i)
                P.row(i) = X[std::size_t(i)].transpose();
            const Mat3 J = P.transpose() * q1_reference_gradients(xi);
            xi -= J.inverse() * (q1_map(X, xi) - p);
        }
        return xi;
    };
    for (std::size_t q = 0; q < ci.points.size(); ++q) {
        for (int a = 0; a < 3; ++a) {
            Vec3 d = Vec3::Zero();
            d(a) = h;
            const Eigen::Matrix<double, 8, 1> fd
                = (q1_shape(invert(ci.points[q] + d)) - q1_shape(invert(ci.points[q] - d)))
                / (2 * h);
            for (int i = 0; i < 8; ++i)
                EXPECT_NEAR(fd(i), ci.gradients[q](i, a), 1e-7) << "q " << q << " a " << a;
        }
        EXPECT_LT(ci.gradients[q].colwise().sum().norm(), 1e-12);
        Mat3 I = Mat3::Zero();
        for (int i = 0; i < 8; ++i)
            I += X[std::size_t(i)] * ci.gradients[q].row(i);
        EXPECT_LT((I - Mat3::Identity()).norm(), 1e-12);
    }
}

TEST(Q1, PartitionOfUnityAndVolume) {
    for (double x : { -1.0, -0.3, 0.5 })
        EXPECT_NEAR(q1_shape(Vec3(x, 0.2, -0.9)).sum(), 1.0, 1e-15);
    // Box [0,2]x[0,1]x[0,1.5]: volume 3, each node gets 3/8.
    std::array<Vec3, 8> X;
    const auto& R = q1_reference_nodes();
    for (int i = 0; i < 8; ++i)
        X[std::size_t(i)] = Vec3((R(i, 0) + 1), 0.5 * (R(i, 1) + 1), 0.75 * (R(i, 2) + 1));
    const CellIntegration ci = q1_integration(X, 2);
    double w = 0;
    for (double v : ci.weights)
        w += v;
    EXPECT_NEAR(w, 3.0, 1e-14);
    for (int i = 0; i < 8; ++i)
        EXPECT_NEAR(ci.lumped_volume(i), 3.0 / 8.0, 1e-14);
    // The distorted hex: volume by the divergence theorem equals the Gauss volume (the Jacobian
    // determinant of a trilinear map is a polynomial of degree <= 2 per axis, so 2x2x2 is exact).
    const auto Y = distorted_hex();
    std::vector<Vec3> pts(Y.begin(), Y.end());
    const mesh::Mesh m = mesh::Mesh::from_hexes(pts, { { 0, 1, 2, 3, 4, 5, 6, 7 } });
    const CellIntegration cd = q1_integration(Y, 2);
    double wd = 0;
    for (double v : cd.weights)
        wd += v;
    EXPECT_NEAR(
        wd, m.cell_volume(0), 1e-3 * wd); // faces are non-planar: divergence volume is approximate
    EXPECT_NEAR(cd.lumped_volume.sum(), wd, 1e-13);
}

TEST(CellBasis, DispatchesByShape) {
    mesh::BoxGrid g;
    g.cells = { 2, 1, 1 };
    const mesh::Mesh tets = mesh::tet_grid(g);
    const mesh::Mesh hexes = mesh::hex_grid(g);
    const BasisOptions opt;
    EXPECT_EQ(integrate_cell(tets, 0, opt).weights.size(), 1u);
    EXPECT_EQ(integrate_cell(hexes, 1, opt).weights.size(), 8u);
    EXPECT_EQ(integrate_cell(hexes, 1, opt).gradients[0].rows(), 8);
    double v = 0;
    for (Index c = 0; c < tets.num_cells(); ++c)
        v += integrate_cell(tets, c, opt).lumped_volume.sum();
    EXPECT_NEAR(v, 1.0, 1e-13);
}
