// Exact integrals of monomials over polyhedra, planar polygons and segments by the divergence
// theorem (003 sec. 6), with no quadrature points: the homogeneous-function recursion of Chin,
// Lasserre and Sukumar (Comput. Mech. 56, 2015), which reduces a volume integral of a degree-q
// monomial to face integrals, a face integral to edge integrals and the face-plane integral of
// lower-degree monomials, an edge integral to its end points. It covers any degree and
// non-convex polyhedra and polygons (Mirtich 1996, which 003 cites, covers degree 2).
// Integrals are taken in the local coordinates xi = (x - origin) / scale, origin near the
// domain's centroid and scale its size, so no term cancels catastrophically.
#pragma once

#include "polycut/common/types.hpp"

#include <span>
#include <vector>

namespace polycut::dg {

/// Integrals over a polyhedron (faces as outward loops of indices into `points`) of every
/// monomial of xi = (x - origin) / scale of degree <= degree (num_monomials(degree), graded
/// order of polynomial.hpp) [m^3]. Faces are simple polygons, planar or warped (then taken as
/// the triangles around their mean point); the polyhedron may be non-convex. Throws InputError for
/// degree outside [0, kMaxDegree] or scale <= 0.
VecX polyhedron_moments(const std::vector<Vec3>& points,
    const std::vector<std::vector<Index>>& loops, const Vec3& origin, double scale, int degree);

/// Integrals over a planar simple polygon (a loop of indices into `points`, any orientation) of
/// every monomial of xi = (x - origin) / scale of degree <= degree [m^2].
VecX polygon_moments(const std::vector<Vec3>& points, std::span<const Index> loop,
    const Vec3& origin, double scale, int degree);

/// Vertices further than this fraction of a loop's size from its mean plane make it warped.
inline constexpr double kPlanarTolerance = 1e-12;

/// Whether the loop's vertices lie in one plane (to kPlanarTolerance of its size). Warped
/// loops (a cut's snapped nodes, moved nodes) are integrated as the triangles joining their
/// mean point to each edge, by the volume moments here and by face_integral_parts.
bool is_planar(const std::vector<Vec3>& points, std::span<const Index> loop);

/// Unit normal of a planar polygon by Newell's method, oriented by the loop (right-hand rule),
/// and its area [m^2] (0 and a zero normal for a degenerate loop).
Vec3 polygon_normal(const std::vector<Vec3>& points, std::span<const Index> loop, double* area);

} // namespace polycut::dg
