// One-dimensional Gauss rules (Gauss-Legendre and Gauss-Jacobi) by the Golub-Welsch algorithm:
// the nodes are the eigenvalues of the Jacobi matrix of the orthogonal polynomials' three-term
// recurrence, the weights the squared first components of its eigenvectors times the weight
// function's total mass (Golub & Welsch 1969, Math. Comp. 23:221).
#pragma once

#include <vector>

namespace polycut::quadrature {

/// A one-dimensional rule: nodes and weights.
struct Rule1d {
    std::vector<double> nodes;
    std::vector<double> weights;
};

/// n-point Gauss-Legendre rule on [-1, 1] (exact for polynomials of degree <= 2n - 1); n >= 1.
Rule1d gauss_legendre(int n);

/// n-point Gauss-Jacobi rule on [0, 1] for the weight (1 - t)^alpha (exact for p(t) (1 - t)^alpha
/// with p of degree <= 2n - 1); n >= 1, alpha > -1 integer or real.
Rule1d gauss_jacobi_01(int n, double alpha);

} // namespace polycut::quadrature
