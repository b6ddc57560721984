// Composite quadrature on a polyhedron by centroid tetrahedralization (001 sec. 5, 000 sec. 4
// "reference rule"): each face is fanned around its area centroid, each fan triangle is joined to
// the cell's volume centroid, and a tet rule is mapped onto every sub-tet. Works for non-convex
// cells too: a sub-tet that comes out inverted gets negative weights, and the signed sum stays
// exact for polynomials as long as the face loops are closed and outward.
#pragma once

#include "polycut/common/types.hpp"

#include <vector>

namespace polycut::quadrature {

/// A quadrature point in physical space.
struct QuadPoint {
    Vec3 point = Vec3::Zero(); ///< position [m]
    double weight = 0; ///< weight [m^3]; the weights of a rule sum to the volume
};

/// Rule of a tet with vertices a, b, c, d exact for total degree <= degree; weights are the
/// signed volume times the reference weights (negative for an inverted tet).
std::vector<QuadPoint> rule_on_tet(
    const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int degree);

/// Composite rule on the polyhedron with outward face `loops` (indices into `points`), exact for
/// total degree <= degree. Faces may be non-convex polygons whose centroid fan covers them (any
/// star-shaped face with respect to its centroid); degenerate sub-tets are skipped.
std::vector<QuadPoint> rule_on_polyhedron(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, int degree);

} // namespace polycut::quadrature
