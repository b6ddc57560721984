#include "polycut/geometry/affine_fit.hpp"

#include <Eigen/Dense>

namespace polycut::geometry {

AffineFit fit_affine(std::span<const Vec3> rest, std::span<const Vec3> world)
{
    AffineFit fit;
    const std::size_t n = rest.size();
    if (n == 0 || world.size() != n) {
        fit.ok = false;
        return fit;
    }
    for (std::size_t i = 0; i < n; ++i) {
        fit.rest_centroid += rest[i];
        fit.world_centroid += world[i];
    }
    fit.rest_centroid /= double(n);
    fit.world_centroid /= double(n);
    Mat3 XX = Mat3::Zero(); // sum dX dX^T
    Mat3 xX = Mat3::Zero(); // sum dx dX^T
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 dX = rest[i] - fit.rest_centroid;
        const Vec3 dx = world[i] - fit.world_centroid;
        XX += dX * dX.transpose();
        xX += dx * dX.transpose();
    }
    // The rest points must span 3D: smallest eigenvalue of XX not negligible.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(XX, Eigen::EigenvaluesOnly);
    const double largest = eig.eigenvalues()(2);
    Eigen::LDLT<Mat3> ldlt(XX);
    if (largest <= 0 || eig.eigenvalues()(0) < 1e-12 * largest) {
        fit.ok = false;
        fit.A = Mat3::Identity();
    } else {
        // A XX = xX  =>  A = xX XX^-1 (XX symmetric)
        fit.A = ldlt.solve(xX.transpose()).transpose();
    }
    fit.t = fit.world_centroid - fit.A * fit.rest_centroid;
    return fit;
}

Mat3 polar_rotation(const Mat3& A)
{
    Eigen::JacobiSVD<Mat3> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 U = svd.matrixU();
    const Mat3 V = svd.matrixV();
    if ((U * V.transpose()).determinant() < 0)
        U.col(2) *= -1.0; // singular values are sorted: flip the smallest
    return U * V.transpose();
}

} // namespace polycut::geometry
