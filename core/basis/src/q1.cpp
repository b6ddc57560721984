#include "polycut/basis/q1.hpp"

#include "polycut/common/error.hpp"
#include "polycut/quadrature/hex_rules.hpp"

#include <Eigen/Dense>

namespace polycut::basis {

const Eigen::Matrix<double, 8, 3>& q1_reference_nodes() {
    static const Eigen::Matrix<double, 8, 3> kNodes = [] {
        Eigen::Matrix<double, 8, 3> m;
        m << -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1;
        return m;
    }();
    return kNodes;
}

Eigen::Matrix<double, 8, 1> q1_shape(const Vec3& xi) {
    const auto& R = q1_reference_nodes();
    Eigen::Matrix<double, 8, 1> N;
    for (int i = 0; i < 8; ++i)
        N(i) = 0.125 * (1 + R(i, 0) * xi.x()) * (1 + R(i, 1) * xi.y()) * (1 + R(i, 2) * xi.z());
    return N;
}

Eigen::Matrix<double, 8, 3> q1_reference_gradients(const Vec3& xi) {
    const auto& R = q1_reference_nodes();
    Eigen::Matrix<double, 8, 3> D;
    for (int i = 0; i < 8; ++i) {
        const double a = 1 + R(i, 0) * xi.x(), b = 1 + R(i, 1) * xi.y(), c = 1 + R(i, 2) * xi.z();
        D(i, 0) = 0.125 * R(i, 0) * b * c;
        D(i, 1) = 0.125 * a * R(i, 1) * c;
        D(i, 2) = 0.125 * a * b * R(i, 2);
    }
    return D;
}

Vec3 q1_map(const std::array<Vec3, 8>& X, const Vec3& xi) {
    const auto N = q1_shape(xi);
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < 8; ++i)
        p += N(i) * X[std::size_t(i)];
    return p;
}

CellIntegration q1_integration(const std::array<Vec3, 8>& X, int n) {
    Eigen::Matrix<double, 8, 3> P;
    for (int i = 0; i < 8; ++i)
        P.row(i) = X[std::size_t(i)].transpose();
    const double scale = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
    const auto rule = quadrature::hex_rule(n);
    CellIntegration ci;
    ci.lumped_volume = VecX::Zero(8);
    for (const auto& q : rule) {
        const Eigen::Matrix<double, 8, 3> D = q1_reference_gradients(q.xi);
        const Mat3 J = P.transpose() * D; // J(a, b) = d x_a / d xi_b
        const double det = J.determinant();
        if (!(det > 1e-14 * scale * scale * scale))
            throw MeshError(-1, -1, "Q1 hex with non-positive Jacobian at a quadrature point");
        // grad_x N = J^-T grad_xi N, as rows: D J^-1.
        const Eigen::Matrix<double, 8, 3> G = D * J.inverse();
        const double w = q.weight * det;
        ci.points.push_back(q1_map(X, q.xi));
        ci.weights.push_back(w);
        ci.gradients.emplace_back(G);
        ci.lumped_volume += w * q1_shape(q.xi);
    }
    return ci;
}

} // namespace polycut::basis
