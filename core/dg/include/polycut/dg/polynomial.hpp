// Trivariate polynomials as coefficient vectors over the graded monomial list (1; x, y, z; x^2,
// xy, xz, y^2, yz, z^2; ...): the algebra the DG module (seed 003) builds its bases, stiffness and
// face terms from. Everything is exact (no quadrature): a product of two polynomials is
// integrated as a dot product with the domain's monomial moments (polyhedron_moments.hpp).
#pragma once

#include "polycut/common/types.hpp"

#include <array>

namespace polycut::dg {

/// Highest total degree the tables cover (products of degree-2 bases with degree-6 data, and
/// the squared error of a degree-6 manufactured solution in tests).
inline constexpr int kMaxDegree = 12;

/// Number of monomials of total degree <= d in three variables: (d+1)(d+2)(d+3)/6.
constexpr int num_monomials(int d) {
    return d < 0 ? 0 : (d + 1) * (d + 2) * (d + 3) / 6;
}

/// Exponents (a, b, c) of monomial k, graded order (all of degree q before degree q + 1).
const std::array<int, 3>& exponent(int k);
/// Index of x^a y^b z^c; -1 when an exponent is negative. a + b + c <= kMaxDegree.
int monomial_index(int a, int b, int c);

/// Values of all monomials of degree <= d at xi (num_monomials(d)).
VecX monomial_values(int d, const Vec3& xi);

/// Product of p (degree dp) and q (degree dq): coefficients of degree dp + dq.
VecX multiply(const VecX& p, int dp, const VecX& q, int dq);

/// d/dxi_axis as a matrix D (num_monomials(d) x num_monomials(d - 1)): the derivative of the
/// polynomial with coefficient row c is the row c * D.
MatX derivative_matrix(int d, int axis);

/// Change of variables xi = shift + scale * zeta as a matrix R (num_monomials(d) squared): the
/// polynomial with coefficient row c in xi has the coefficient row c * R in zeta. Monomials of
/// degree <= d' < d map into the first num_monomials(d') entries, so the leading block of R is the
/// matrix of degree d'.
MatX rebase_matrix(int d, const Vec3& shift, double scale);

/// Gram matrix of the monomials of degree <= d over a domain: G(r, s) = moments[index of
/// monomial r * monomial s]. moments: the domain's moments of degree >= 2d.
MatX monomial_gram(const VecX& moments, int d);

} // namespace polycut::dg
