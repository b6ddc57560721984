#include "polycut/basis/p1.hpp"

#include "polycut/common/error.hpp"

#include <Eigen/Dense>

namespace polycut::basis {

Eigen::Matrix<double, 4, 3> p1_gradients(const std::array<Vec3, 4>& X) {
    // Columns of Dm are the edges from node 0; phi_k = (Dm^-1 (p - X0))_k for k = 1..3.
    Mat3 Dm;
    Dm << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    const double det = Dm.determinant();
    const double scale = (X[1] - X[0]).norm() + (X[2] - X[0]).norm() + (X[3] - X[0]).norm();
    if (!(det > 1e-14 * scale * scale * scale))
        throw MeshError(-1, -1, "P1 tet with non-positive volume");
    const Mat3 Dinv = Dm.inverse();
    Eigen::Matrix<double, 4, 3> G;
    G.bottomRows<3>() = Dinv;
    G.row(0) = -Dinv.colwise().sum();
    return G;
}

Eigen::Vector4d p1_shape(const std::array<Vec3, 4>& X, const Vec3& p) {
    Mat3 Dm;
    Dm << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    const Vec3 l = Dm.partialPivLu().solve(p - X[0]);
    return { 1.0 - l.sum(), l.x(), l.y(), l.z() };
}

CellIntegration p1_integration(const std::array<Vec3, 4>& X) {
    const Eigen::Matrix<double, 4, 3> G = p1_gradients(X);
    const double vol = (X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0])) / 6.0;
    CellIntegration ci;
    ci.points = { 0.25 * (X[0] + X[1] + X[2] + X[3]) };
    ci.weights = { vol };
    ci.gradients = { MatX3(G) };
    ci.lumped_volume = VecX::Constant(4, vol / 4.0);
    return ci;
}

} // namespace polycut::basis
