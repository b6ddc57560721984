#include "polycut/quadrature/gauss_jacobi.hpp"

#include "polycut/common/error.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace polycut::quadrature {
namespace {
// Golub-Welsch for the Jacobi weight (1 - x)^a (1 + x)^b on [-1, 1].
Rule1d golub_welsch_jacobi(int n, double a, double b) {
    if (n < 1)
        throw InputError("n", "a Gauss rule needs at least one point");
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
    for (int k = 0; k < n; ++k) {
        const double s = 2.0 * k + a + b;
        // Diagonal: (b^2 - a^2) / (s (s + 2)); the k = 0 term is (b - a) / (a + b + 2).
        J(k, k) = (k == 0) ? (b - a) / (a + b + 2.0) : (b * b - a * a) / (s * (s + 2.0));
        if (k + 1 < n) {
            const double m = k + 1.0;
            const double t = 2.0 * m + a + b;
            const double num = 4.0 * m * (m + a) * (m + b) * (m + a + b);
            const double den = t * t * (t + 1.0) * (t - 1.0);
            J(k, k + 1) = J(k + 1, k) = std::sqrt(num / den);
        }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(J);
    const double mu0 = std::exp((a + b + 1.0) * std::log(2.0) + std::lgamma(a + 1.0)
        + std::lgamma(b + 1.0) - std::lgamma(a + b + 2.0));
    Rule1d r;
    r.nodes.resize(std::size_t(n));
    r.weights.resize(std::size_t(n));
    for (int k = 0; k < n; ++k) {
        r.nodes[std::size_t(k)] = eig.eigenvalues()(k);
        const double v0 = eig.eigenvectors()(0, k);
        r.weights[std::size_t(k)] = mu0 * v0 * v0;
    }
    return r;
}
} // namespace

Rule1d gauss_legendre(int n) {
    return golub_welsch_jacobi(n, 0.0, 0.0);
}

Rule1d gauss_jacobi_01(int n, double alpha) {
    // t = (1 + x) / 2: (1 - t)^alpha dt = 2^-(alpha + 1) (1 - x)^alpha dx.
    Rule1d r = golub_welsch_jacobi(n, alpha, 0.0);
    const double scale = std::pow(2.0, -(alpha + 1.0));
    for (std::size_t k = 0; k < r.nodes.size(); ++k) {
        r.nodes[k] = 0.5 * (1.0 + r.nodes[k]);
        r.weights[k] *= scale;
    }
    return r;
}

} // namespace polycut::quadrature
