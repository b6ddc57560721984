// Quadrature rules on the tetrahedron in barycentric form, so they apply to any tet: a point is
// sum_k bary[k] * vertex[k], its weight is weight * volume.
#pragma once

#include <array>
#include <vector>

namespace polycut::quadrature {

/// A point of a tet rule: barycentric coordinates (sum 1) and a weight as a fraction of the
/// tet's volume (the weights of a rule sum to 1).
struct BaryPoint {
    std::array<double, 4> bary {};
    double weight = 0;
};

/// A rule exact for all polynomials of total degree <= degree (degree >= 0), with positive
/// weights and all points inside the tet:
///  - degree 0, 1: the centroid (1 point);
///  - degree 2: the symmetric 4-point rule (Hammer, Marlowe & Stroud 1956; Keast 1986 rule #2);
///  - degree >= 3: Stroud's conical product rule T3:(2n-1)-1, n = ceil((degree + 1) / 2) Gauss-
///    Jacobi points per collapsed axis, n^3 points (Stroud 1971, "Approximate calculation of
///    multiple integrals", sec. 2.7; 27 points for degree 5).
/// Throws InputError for degree < 0.
std::vector<BaryPoint> tet_rule(int degree);

/// Grundmann-Moeller rule of index s >= 0, exact for degree 2s + 1 (Grundmann & Moeller 1978,
/// SIAM J. Numer. Anal. 15:282, Theorem 4). Fewer points than tet_rule() (5 for degree 3, 15 for
/// degree 5) but, for s >= 1, some weights are negative.
std::vector<BaryPoint> grundmann_moeller_rule(int s);

} // namespace polycut::quadrature
