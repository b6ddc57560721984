#include "polycut/elasticity/element_stiffness.hpp"

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
// Many-node cells (polyhedra: 3n of 30-500 DOFs, q of 20-500 points). With an isotropic C the
// block of nodes (a, b) is sum_q w_q (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I), so it
// needs only the 3 x 3 blocks M_ab = sum_q w_q g_a g_b^T of M = A A^T, A the 3n x q matrix of
// the stacked sqrt(w_q) g_q: one symmetric rank-q product of (3n)^2 q / 2 multiply-adds at
// matrix product speed. (It was S^T S with S the 6q x 3n stacked sqrt(w_q) L^T B_q, C = L L^T:
// six times the work, a third of a curved stroke's cut ticks through the default block.)
MatX stiffness_by_rank_update(const basis::CellIntegration& ci, double lambda, double mu) {
    const Index n = Index(ci.gradients[0].rows());
    const Index q = Index(ci.gradients.size());
    MatX A(3 * n, q);
    for (Index k = 0; k < q; ++k) {
        const double s = std::sqrt(ci.weights[std::size_t(k)]);
        const MatX3& g = ci.gradients[std::size_t(k)];
        for (Index a = 0; a < n; ++a)
            for (Index i = 0; i < 3; ++i)
                A(3 * a + i, k) = s * g(a, i);
    }
    MatX M = MatX::Zero(3 * n, 3 * n);
    M.selfadjointView<Eigen::Lower>().rankUpdate(A);
    MatX K(3 * n, 3 * n);
    for (Index b = 0; b < n; ++b)
        for (Index a = b; a < n; ++a) {
            // the lower triangle holds M: whole blocks below the diagonal, half of those on it
            const Mat3 Mab = a > b
                ? Mat3(M.block<3, 3>(3 * a, 3 * b))
                : Mat3(M.block<3, 3>(3 * a, 3 * b).selfadjointView<Eigen::Lower>());
            Mat3 block = lambda * Mab + mu * Mab.transpose();
            block.diagonal().array() += mu * Mab.trace();
            K.block<3, 3>(3 * a, 3 * b) = block;
            K.block<3, 3>(3 * b, 3 * a) = block.transpose();
        }
    return K;
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
    if (n > 8 && positive_weights)
        K = stiffness_by_rank_update(ci, lambda, mu);
    else
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
