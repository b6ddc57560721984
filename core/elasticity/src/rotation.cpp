#include "polycut/elasticity/rotation.hpp"

#include "polycut/geometry/affine_fit.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace polycut::elasticity {

bool fit_gradients(std::span<const Vec3> rest, MatX3& G)
{
    const std::size_t n = rest.size();
    G.setZero(Index(n), 3);
    if (n < 4)
        return false;
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : rest)
        c += p;
    c /= double(n);
    Mat3 XX = Mat3::Zero();
    for (const Vec3& p : rest)
        XX += (p - c) * (p - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(XX, Eigen::EigenvaluesOnly);
    if (!(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(2)))
        return false;
    const Mat3 XXinv = XX.inverse();
    for (std::size_t i = 0; i < n; ++i)
        G.row(Index(i)) = (XXinv * (rest[i] - c)).transpose();
    return true;
}

Mat3 polar_rotation_warm(const Mat3& A, const Mat3& guess)
{
    Mat3 X = guess.transpose() * A; // = guess^T R S: polar rotation guess^T R
    const double scale = X.norm();
    if (!(scale > 0) || !std::isfinite(scale))
        return guess;
    for (int it = 0; it < 20; ++it) {
        const double det = X.determinant();
        if (!(det > 1e-6 * scale * scale * scale))
            return geometry::polar_rotation(A); // inverted or nearly flat: SVD with axis flip
        const Mat3 Xinv = X.inverse();
        // Frobenius scaling (Higham 1986 eq. 3.2) only while far from orthogonal.
        const double g = std::sqrt(Xinv.norm() / X.norm());
        const Mat3 next = 0.5 * (g * X + Xinv.transpose() / g);
        const double change = (next - X).norm();
        X = next;
        if (change < 1e-13)
            break;
    }
    return guess * X;
}

} // namespace polycut::elasticity
