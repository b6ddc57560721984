// Element stiffness of P1 and Q1 cells: symmetry, positive semi-definiteness, exactly six rigid
// modes, agreement with the textbook B^T C B, and material parameters.
#include "polycut/basis/p1.hpp"
#include "polycut/basis/q1.hpp"
#include "polycut/common/error.hpp"
#include "polycut/elasticity/element_stiffness.hpp"
#include "polycut/elasticity/rotation.hpp"
#include "polycut/geometry/affine_fit.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <random>

using namespace polycut;
using namespace polycut::elasticity;

namespace {
Material material(double nu) {
    Material m;
    m.youngs_modulus = 2.5e5;
    m.poisson_ratio = nu;
    return m;
}

std::array<Vec3, 8> distorted_hex(unsigned seed) {
    std::array<Vec3, 8> X;
    const auto& R = basis::q1_reference_nodes();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.12, 0.12);
    for (int i = 0; i < 8; ++i)
        X[std::size_t(i)] = 0.5 * (R.row(i).transpose() + Vec3::Ones())
            + Vec3(jitter(rng), jitter(rng), jitter(rng));
    return X;
}

void expect_stiffness_properties(const basis::CellIntegration& ci, const Material& m) {
    const MatX K = element_stiffness(ci, m);
    // Against sum_q w B^T C B.
    MatX ref = MatX::Zero(K.rows(), K.cols());
    const auto C = elasticity_matrix(m);
    for (std::size_t q = 0; q < ci.weights.size(); ++q) {
        const MatX B = strain_displacement(ci.gradients[q]);
        ref += ci.weights[q] * B.transpose() * C * B;
    }
    EXPECT_LT((K - ref).norm(), 1e-12 * ref.norm());
    EXPECT_LT((K - K.transpose()).norm(), 1e-14 * K.norm());
    const Eigen::SelfAdjointEigenSolver<MatX> eig(K);
    const VecX ev = eig.eigenvalues();
    const double largest = ev(ev.size() - 1);
    int zeros = 0;
    for (Index i = 0; i < ev.size(); ++i) {
        EXPECT_GT(ev(i), -1e-12 * largest);
        if (std::abs(ev(i)) < 1e-10 * largest)
            ++zeros;
    }
    EXPECT_EQ(zeros, 6);
    EXPECT_GT(ev(6), 1e-6 * largest); // the seventh mode is a real deformation mode
}
} // namespace

TEST(Material, LameParametersAndValidation) {
    const Material m = material(0.25);
    EXPECT_NEAR(m.mu(), 2.5e5 / 2.5, 1e-9);
    EXPECT_NEAR(m.lambda(), 2.5e5 * 0.25 / (1.25 * 0.5), 1e-9);
    Material bad = m;
    bad.poisson_ratio = 0.5;
    EXPECT_THROW(validate(bad), InputError);
    bad = m;
    bad.youngs_modulus = std::nan("");
    EXPECT_THROW(validate(bad), InputError);
}

TEST(ElementStiffness, P1SymmetricPsdSixRigidModes) {
    const std::array<Vec3, 4> X { Vec3(0.1, 0.0, 0.2), Vec3(1.2, 0.1, 0.0), Vec3(0.3, 0.9, 0.1),
        Vec3(0.2, 0.3, 1.0) };
    for (double nu : { 0.0, 0.3, 0.49 })
        expect_stiffness_properties(basis::p1_integration(X), material(nu));
}

TEST(ElementStiffness, Q1SymmetricPsdSixRigidModesOnDistortedHexes) {
    for (unsigned seed : { 1u, 2u, 3u })
        for (double nu : { 0.0, 0.3, 0.45 })
            expect_stiffness_properties(
                basis::q1_integration(distorted_hex(seed), 2), material(nu));
}

TEST(Rotation, PolarRotationWarmMatchesSvd) {
    std::mt19937 rng(11);
    std::normal_distribution<double> n01;
    for (int trial = 0; trial < 50; ++trial) {
        Mat3 A;
        for (int i = 0; i < 9; ++i)
            A(i / 3, i % 3) = n01(rng);
        A += 2.0 * Mat3::Identity();
        const Mat3 guess
            = Eigen::AngleAxisd(n01(rng), Vec3(n01(rng), n01(rng), n01(rng)).normalized())
                  .toRotationMatrix();
        const Mat3 R = polar_rotation_warm(A, guess);
        const Mat3 ref = geometry::polar_rotation(A);
        EXPECT_LT((R - ref).norm(), 1e-10) << "trial " << trial;
        EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    }
}

TEST(Rotation, FitGradientsGiveTheAffineMap) {
    const auto X = distorted_hex(5);
    MatX3 G;
    ASSERT_TRUE(fit_gradients(X, G));
    Mat3 A0;
    A0 << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2;
    Mat3 A = Mat3::Zero();
    for (int i = 0; i < 8; ++i)
        A += (A0 * X[std::size_t(i)] + Vec3(1, 2, 3)) * G.row(i);
    EXPECT_LT((A - A0).norm(), 1e-12);
}

namespace {
/// Displacement (3n) of the nodes X under u(x) = A x.
VecX affine_field(const std::vector<Vec3>& X, const Mat3& A) {
    VecX u(3 * Index(X.size()));
    for (std::size_t i = 0; i < X.size(); ++i)
        u.segment<3>(3 * Index(i)) = A * X[i];
    return u;
}
} // namespace

// B-bar mean dilatation (basis::VolumetricRule::MeanDilatation, issue 17 item 5): the same
// rigid-mode kernel, the same energy for every constant strain (the patch test: the mean of a
// constant dilatation is itself), identical to P1 on a tet, and stiffer by far less than full
// integration against the bending mode u_x = x y of a hex at nu -> 0.5 (the mode full
// integration locks on: its pointwise dilatation y is not zero, its mean over the cell is).
TEST(ElementStiffness, MeanDilatationKeepsRigidModesAndConstantStrains) {
    for (unsigned seed : { 3u, 11u }) {
        const auto X = distorted_hex(seed);
        const basis::CellIntegration ci = basis::q1_integration(X, 2);
        for (double nu : { 0.0, 0.3, 0.4999 }) {
            const MatX K
                = element_stiffness(ci, material(nu), basis::VolumetricRule::MeanDilatation);
            EXPECT_LT((K - K.transpose()).norm(), 1e-13 * K.norm());
            const Eigen::SelfAdjointEigenSolver<MatX> eig(K);
            const VecX ev = eig.eigenvalues();
            int zeros = 0;
            for (Index i = 0; i < ev.size(); ++i) {
                EXPECT_GT(ev(i), -1e-12 * ev(ev.size() - 1));
                zeros += std::abs(ev(i)) < 1e-10 * ev(ev.size() - 1) ? 1 : 0;
            }
            EXPECT_EQ(zeros, 6) << "nu " << nu;
            const MatX Kfull = element_stiffness(ci, material(nu));
            std::mt19937 rng(seed);
            std::uniform_real_distribution<double> d(-0.01, 0.01);
            Mat3 A;
            for (int k = 0; k < 9; ++k)
                A(k / 3, k % 3) = d(rng);
            const VecX u = affine_field({ X.begin(), X.end() }, A);
            const double e_bar = u.dot(K * u), e_full = u.dot(Kfull * u);
            EXPECT_NEAR(e_bar, e_full, 1e-11 * e_full) << "nu " << nu;
        }
    }
}

TEST(ElementStiffness, MeanDilatationIsP1OnTetsAndUnlocksHexBending) {
    const std::array<Vec3, 4> T { Vec3(0.1, 0.0, 0.2), Vec3(1.2, 0.1, 0.0), Vec3(0.3, 0.9, 0.1),
        Vec3(0.2, 0.3, 1.0) };
    const auto ti = basis::p1_integration(T);
    const MatX Kp1 = element_stiffness(ti, material(0.49));
    EXPECT_LT(
        (element_stiffness(ti, material(0.49), basis::VolumetricRule::MeanDilatation) - Kp1).norm(),
        1e-12 * Kp1.norm());
    // Unit cube, bending u_x = (x - 1/2)(y - 1/2): at nu = 0.4999 full integration stores
    // lambda-sized energy, the mean dilatation (zero) none of it.
    std::array<Vec3, 8> X;
    const auto& R = basis::q1_reference_nodes();
    for (int i = 0; i < 8; ++i)
        X[std::size_t(i)] = 0.5 * (R.row(i).transpose() + Vec3::Ones());
    const auto ci = basis::q1_integration(X, 2);
    VecX u = VecX::Zero(24);
    for (int i = 0; i < 8; ++i)
        u(3 * i) = (X[std::size_t(i)].x() - 0.5) * (X[std::size_t(i)].y() - 0.5);
    const Material m = material(0.4999);
    const double e_full = u.dot(element_stiffness(ci, m) * u);
    const double e_bar = u.dot(element_stiffness(ci, m, basis::VolumetricRule::MeanDilatation) * u);
    // Exact: deviatoric energy only, ~mu; full integration adds ~lambda / 36 (lambda / mu ~ 1e4).
    EXPECT_LT(e_bar, 1.0 * m.mu());
    EXPECT_GT(e_full, 50 * e_bar);
}

TEST(ElementStiffness, ManyNodeCellsMatchTheTextbookSumForEveryVolumetricRule) {
    // Cells of more than 8 nodes take a rank-q product of the stacked gradients (the 3 x 3
    // blocks of sum_q w_q g_a g_b^T); it must equal sum_q w_q B_q^T C B_q entry by entry, C the
    // full, the deviatoric (NodalAverage) and the deviatoric plus the cell-mean volumetric term
    // (MeanDilatation). Random gradients of 13 nodes at 29 points, positive weights.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.1, 1.0);
    basis::CellIntegration ci;
    const Index n = 13;
    for (int q = 0; q < 29; ++q) {
        MatX3 g(n, 3);
        for (Index a = 0; a < n; ++a)
            g.row(a) = Eigen::RowVector3d(u(rng), u(rng), u(rng));
        ci.gradients.push_back(g);
        ci.weights.push_back(w(rng));
        ci.points.push_back(Vec3::Zero());
    }
    const Material m = material(0.45);
    const double kappa = m.lambda() + 2.0 * m.mu() / 3.0;
    for (const auto rule : { basis::VolumetricRule::Full, basis::VolumetricRule::NodalAverage,
             basis::VolumetricRule::MeanDilatation }) {
        auto C = elasticity_matrix(m);
        if (rule != basis::VolumetricRule::Full)
            C.topLeftCorner<3, 3>().array() -= kappa;
        MatX ref = MatX::Zero(3 * n, 3 * n);
        double V = 0;
        VecX bbar = VecX::Zero(3 * n);
        for (std::size_t q = 0; q < ci.gradients.size(); ++q) {
            const MatX B = strain_displacement(ci.gradients[q]);
            ref += ci.weights[q] * B.transpose() * C * B;
            V += ci.weights[q];
            for (Index a = 0; a < n; ++a)
                bbar.segment<3>(3 * a) += ci.weights[q] * ci.gradients[q].row(a).transpose();
        }
        if (rule == basis::VolumetricRule::MeanDilatation)
            ref += (kappa / V) * bbar * bbar.transpose();
        const MatX K = element_stiffness(ci, m, rule);
        // Relative to the largest entry: the two sums differ by round-off only.
        EXPECT_LT((K - ref).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff())
            << "rule " << int(rule);
        EXPECT_LT((K - K.transpose()).norm(), 1e-14 * K.norm()) << "rule " << int(rule);
    }
}
