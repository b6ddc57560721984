#include "polycut/elasticity/element_stiffness.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace polycut::elasticity {

MatX strain_displacement(const MatX3& g) {
    const Index n = Index(g.rows());
    MatX B = MatX::Zero(6, 3 * n);
    for (Index i = 0; i < n; ++i) {
        const double gx = g(i, 0), gy = g(i, 1), gz = g(i, 2);
        B(0, 3 * i + 0) = gx;
        B(1, 3 * i + 1) = gy;
        B(2, 3 * i + 2) = gz;
        B(3, 3 * i + 1) = gz; // yz
        B(3, 3 * i + 2) = gy;
        B(4, 3 * i + 0) = gz; // xz
        B(4, 3 * i + 2) = gx;
        B(5, 3 * i + 0) = gy; // xy
        B(5, 3 * i + 1) = gx;
    }
    return B;
}

namespace {
// Many-node cells (polyhedra: 3n of 30-500 DOFs, q of 20-500 points): one symmetric rank-k
// product K = S^T S with S the stacked rows sqrt(w_q) L^T B_q (C = L L^T), which runs at matrix
// product speed instead of n^2 q 3x3 block updates (10x faster at 100+ nodes).
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// L^T with C = L L^T: Cholesky for a positive definite C; for the deviatoric part, which has
/// m in its kernel, diag(sqrt(eigenvalues)) V^T.
Mat6 root_transpose(const Mat6& C, bool semi_definite) {
    if (!semi_definite)
        return Eigen::LLT<Mat6>(C).matrixL().transpose();
    const Eigen::SelfAdjointEigenSolver<Mat6> eig(C);
    return eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal()
        * eig.eigenvectors().transpose();
}

MatX stiffness_by_rank_update(const basis::CellIntegration& ci, const Mat6& C, bool semi_definite) {
    const Index n = Index(ci.gradients[0].rows());
    const Mat6 Lt = root_transpose(C, semi_definite);
    MatX S(6 * Index(ci.gradients.size()), 3 * n);
    for (std::size_t q = 0; q < ci.gradients.size(); ++q)
        S.middleRows<6>(6 * Index(q)).noalias()
            = std::sqrt(ci.weights[q]) * (Lt * strain_displacement(ci.gradients[q]));
    MatX K = MatX::Zero(3 * n, 3 * n);
    K.selfadjointView<Eigen::Lower>().rankUpdate(S.transpose());
    return K.selfadjointView<Eigen::Lower>();
}
/// sum_q w_q B_q^T C B_q block by block, C with Lame parameters (lambda, mu).
MatX pointwise_stiffness(const basis::CellIntegration& ci, double lambda, double mu, Index n) {
    MatX K = MatX::Zero(3 * n, 3 * n);
    for (std::size_t q = 0; q < ci.gradients.size(); ++q) {
        const MatX3& g = ci.gradients[q];
        const double w = ci.weights[q];
        for (Index i = 0; i < n; ++i) {
            const Vec3 gi = g.row(i).transpose();
            for (Index j = 0; j < n; ++j) {
                const Vec3 gj = g.row(j).transpose();
                Mat3 block = lambda * gi * gj.transpose() + mu * gj * gi.transpose();
                block.diagonal().array() += mu * gi.dot(gj);
                K.block<3, 3>(3 * i, 3 * j) += w * block;
            }
        }
    }
    // Exact symmetry (the blocks are symmetric up to round-off).
    return 0.5 * (K + K.transpose());
}
} // namespace

MatX element_stiffness(
    const basis::CellIntegration& ci, const Material& material, basis::VolumetricRule rule) {
    const bool mean_dilatation = rule == basis::VolumetricRule::MeanDilatation;
    // NodalAverage: the cell keeps the deviatoric part only (ElasticModel adds the nodal term).
    const bool deviatoric = rule != basis::VolumetricRule::Full;
    const double mu = material.mu();
    const double kappa = material.lambda() + 2.0 * mu / 3.0; // bulk modulus [Pa]
    // Mean dilatation: the pointwise part with the deviatoric C_dev = lambda' m m^T + mu D,
    // lambda' = lambda - kappa = -2 mu / 3 (C_dev m = 0), plus the cell-mean volumetric term.
    const double lambda = deviatoric ? -2.0 * mu / 3.0 : material.lambda();
    const Index n = ci.gradients.empty() ? 0 : Index(ci.gradients[0].rows());
    const bool positive_weights
        = std::all_of(ci.weights.begin(), ci.weights.end(), [](double w) { return w >= 0; });
    MatX K;
    if (n > 8 && positive_weights) {
        Mat6 C = elasticity_matrix(material);
        if (deviatoric)
            C.topLeftCorner<3, 3>().array() -= kappa;
        K = stiffness_by_rank_update(ci, C, deviatoric);
    } else
        K = pointwise_stiffness(ci, lambda, mu, n);
    if (mean_dilatation && n > 0) {
        // kappa V bbar bbar^T with bbar = (1/V) sum_q w_q [g_q,i] (the divergence row)
        double V = 0;
        VecX bbar = VecX::Zero(3 * n);
        for (std::size_t q = 0; q < ci.gradients.size(); ++q) {
            V += ci.weights[q];
            for (Index i = 0; i < n; ++i)
                bbar.segment<3>(3 * i) += ci.weights[q] * ci.gradients[q].row(i).transpose();
        }
        if (V > 0)
            K.noalias() += (kappa / V) * bbar * bbar.transpose();
    }
    return K;
}

void stabilize_non_affine(MatX& Ke, const MatX3& dX, const MatX3& G, double tau) {
    // P u_i = mean(u) + (sum_j u_j G_j^T) dX_i: the affine least-squares fit of the cell's node
    // values (rotation.hpp), P_ij = 1/n + dX_i . G_j, symmetric and idempotent, so I - P is the
    // orthogonal projection onto the non-affine modes and a positive semi-definite stiffness.
    const Index n = dX.rows();
    const MatX S
        = MatX::Identity(n, n) - MatX::Constant(n, n, 1.0 / double(n)) - dX * G.transpose();
    const double k = tau * Ke.trace() / double(3 * n);
    for (Index i = 0; i < n; ++i)
        for (Index j = 0; j < n; ++j)
            for (Index a = 0; a < 3; ++a)
                Ke(3 * i + a, 3 * j + a) += k * S(i, j);
}

} // namespace polycut::elasticity
