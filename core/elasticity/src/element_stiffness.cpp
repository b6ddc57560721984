#include "polycut/elasticity/element_stiffness.hpp"

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

MatX element_stiffness(const basis::CellIntegration& ci, const Material& material) {
    const double mu = material.mu(), lambda = material.lambda();
    const Index n = ci.gradients.empty() ? 0 : Index(ci.gradients[0].rows());
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

} // namespace polycut::elasticity
