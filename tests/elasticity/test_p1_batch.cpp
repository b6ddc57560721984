// The batched P1 kernel (core/elasticity/src/p1_batch.cpp) against the element definition:
// per tet f = -R Ke (R^T (x - x_c) - (X - X_c)) and K = R Ke R^T with R the SVD polar rotation of
// the deformation gradient, assembled densely here. Covers full batches and a remainder, the
// compact and the full scatter (partly fixed nodes), the vectorized rotation update (small
// rotation since the last assembly) and its scalar fall-back (90 degrees from a cold start).
#include "helpers.hpp"
#include "polycut/geometry/affine_fit.hpp"

using namespace polycut;
using namespace polycut::elasticity;

namespace {

struct Reference {
    VecX f; ///< full (3#N) [N]
    MatX K; ///< reduced, dense [N/m]
    std::vector<Mat3> R;
};

Reference reference(const ElasticModel& model, const MatX3& x) {
    const mesh::Mesh& m = model.mesh();
    Reference ref;
    ref.f.setZero(3 * x.rows());
    ref.K.setZero(model.num_free_dofs(), model.num_free_dofs());
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& nodes = m.cells[std::size_t(c)].nodes;
        const MatX& G = model.cell_integration(c).gradients[0];
        Vec3 xc = Vec3::Zero(), Xc = Vec3::Zero();
        for (Index i : nodes) {
            xc += x.row(i).transpose() / 4.0;
            Xc += m.rest[std::size_t(i)] / 4.0;
        }
        Mat3 F = Mat3::Zero();
        for (int i = 0; i < 4; ++i)
            F += (x.row(nodes[std::size_t(i)]).transpose() - xc) * G.row(i);
        const Mat3 R = geometry::polar_rotation(F);
        ref.R.push_back(R);
        using Mat12 = Eigen::Matrix<double, 12, 12>;
        using Vec12 = Eigen::Matrix<double, 12, 1>;
        const Mat12 Ke = model.cell_stiffness(c);
        Vec12 u;
        Mat12 Rb = Mat12::Zero();
        for (int i = 0; i < 4; ++i) {
            const Index n = nodes[std::size_t(i)];
            u.segment<3>(3 * i)
                = R.transpose() * (x.row(n).transpose() - xc) - (m.rest[std::size_t(n)] - Xc);
            Rb.block<3, 3>(3 * i, 3 * i) = R;
        }
        const Vec12 f = -Rb * (Ke * u);
        const Mat12 Kc = Rb * Ke * Rb.transpose();
        for (int i = 0; i < 4; ++i) {
            const Index ni = nodes[std::size_t(i)];
            ref.f.segment<3>(3 * ni) += f.segment<3>(3 * i);
            for (int j = 0; j < 4; ++j)
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        const Index r = model.dof_map()[std::size_t(3 * ni + a)];
                        const Index s = model.dof_map()[std::size_t(3 * nodes[std::size_t(j)] + b)];
                        if (r != kNone && s != kNone)
                            ref.K(r, s) += Kc(3 * i + a, 3 * j + b);
                    }
        }
    }
    return ref;
}

} // namespace

TEST(P1Batch, MatchesElementDefinitionWithFallbackAndBothScatters) {
    mesh::BoxGrid g;
    g.lo = Vec3(0, 0, 0);
    g.hi = Vec3(0.3, 0.1, 0.1);
    g.cells = { 3, 1, 1 };
    const mesh::Mesh m = mesh::tet_grid(g, mesh::TetSplit::Five); // 15 tets: 3 batches + 3
    ASSERT_EQ(m.num_cells(), 15);
    // Node 0 fixed; node 5 only in y (its tets take the full scatter, the others the compact).
    std::vector<std::uint8_t> fixed;
    for (Index k = 0; k < 3 * m.num_nodes(); ++k)
        fixed.push_back(k < 3 || k == 3 * 5 + 1 ? 1 : 0);
    Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.45;
    ElasticModel model(m, mat, {}, fixed);

    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    const Mat3 Q90
        = Eigen::AngleAxisd(M_PI / 2, Vec3(0.3, 1, -0.2).normalized()).toRotationMatrix();
    const Mat3 Qs = Eigen::AngleAxisd(0.02, Vec3(1, -0.5, 0.7).normalized()).toRotationMatrix();
    MatX3 x(m.num_nodes(), 3);
    for (Index i = 0; i < x.rows(); ++i)
        x.row(i) = (Q90 * (1.1 * m.rest[std::size_t(i)] + Vec3(jitter(rng), jitter(rng), 0)))
                       .transpose();
    solve::SparseMatrix K = model.make_matrix();
    VecX f;
    // First assembly: 90 degrees from the identity (scalar fall-back); second: a small further
    // rotation and stretch from the cached rotations (vectorized Newton).
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1)
            for (Index i = 0; i < x.rows(); ++i)
                x.row(i)
                    = (Qs * x.row(i).transpose() + Vec3(jitter(rng), 0, jitter(rng))).transpose();
        model.assemble(x, ForceMode::Corotated, &K, &f);
        const Reference ref = reference(model, x);
        const double fscale = ref.f.cwiseAbs().maxCoeff();
        const double kscale = ref.K.cwiseAbs().maxCoeff();
        ASSERT_GT(fscale, 0);
        EXPECT_LT((f - ref.f).cwiseAbs().maxCoeff(), 1e-10 * fscale) << "pass " << pass;
        EXPECT_LT((MatX(K) - ref.K).cwiseAbs().maxCoeff(), 1e-12 * kscale) << "pass " << pass;
        for (Index c = 0; c < m.num_cells(); ++c)
            EXPECT_LT((model.cell_rotation(c) - ref.R[std::size_t(c)]).norm(), 1e-9)
                << "pass " << pass << " cell " << c;
    }
    // Linear mode: R = I.
    model.assemble(x, ForceMode::Linear, &K, &f);
    VecX u(3 * x.rows());
    for (Index i = 0; i < x.rows(); ++i)
        u.segment<3>(3 * i) = x.row(i).transpose() - m.rest[std::size_t(i)];
    VecX f_lin = VecX::Zero(3 * x.rows());
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& nodes = m.cells[std::size_t(c)].nodes;
        VecX uc(12);
        for (int i = 0; i < 4; ++i)
            uc.segment<3>(3 * i) = u.segment<3>(3 * nodes[std::size_t(i)]);
        const VecX fc = -(model.cell_stiffness(c) * uc);
        for (int i = 0; i < 4; ++i)
            f_lin.segment<3>(3 * nodes[std::size_t(i)]) += fc.segment<3>(3 * i);
    }
    EXPECT_LT((f - f_lin).cwiseAbs().maxCoeff(), 1e-10 * f_lin.cwiseAbs().maxCoeff());
}
