#include "polycut/elasticity/rotation.hpp"

#include "polycut/geometry/affine_fit.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace polycut::elasticity {

bool fit_gradients(std::span<const Vec3> rest, MatX3& G) {
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

Mat3 polar_rotation_warm(const Mat3& A, const Mat3& guess) {
    Mat3 X = guess.transpose() * A; // = guess^T R S: polar rotation guess^T R
    const double scale = X.norm();
    if (!(scale > 0) || !std::isfinite(scale))
        return guess;
    // Fast path when the warm start is close (the usual case within a time step): Newton on the
    // rotation. With X = (I + W) S, skew(X) = (W S + S W) / 2, i.e. (tr(S) I - S) w = 2 k for
    // w = axial(W), k = axial(skew(X)); the step is applied as the exact rotation Cayley(w / 2)
    // and X <- Q^T X. Quadratic convergence, ~100 flops per iteration, no 3x3 inverse of X.
    if (X.determinant() > 1e-6 * scale * scale * scale) {
        Mat3 Q = Mat3::Identity();
        Mat3 Y = X;
        for (int it = 0; it < 8; ++it) {
            const Vec3 k(
                0.5 * (Y(2, 1) - Y(1, 2)), 0.5 * (Y(0, 2) - Y(2, 0)), 0.5 * (Y(1, 0) - Y(0, 1)));
            Mat3 M = -0.5 * (Y + Y.transpose());
            M.diagonal().array() -= M.trace();
            const double dm = M.determinant();
            const double tm = M.trace();
            if (!(tm > 0) || !(dm > 1e-9 * tm * tm * tm))
                break; // stretch far from positive definite: Higham below
            const Vec3 w = M.inverse() * (2.0 * k);
            const double wn = w.norm();
            if (it == 0 && !(wn < 0.5))
                break; // warm start too far
            // Cayley transform with c = w / 2: an exact rotation, equal to exp(w) to O(|w|^3).
            const Vec3 c = 0.5 * w;
            Mat3 C;
            C << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0;
            const Mat3 step = Mat3::Identity() + (2.0 / (1.0 + c.squaredNorm())) * (C + C * C);
            Q = Q * step;
            Y = step.transpose() * Y;
            if (wn < 1e-5)
                return guess * Q;
            if (!(wn < 1.0))
                break;
        }
    }
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
