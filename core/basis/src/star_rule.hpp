// Internal to the polyhedral bases (mean value and harmonic): the composite reference rule of a
// polyhedron, a star tetrahedralization from one interior point (the centroid for convex cells)
// over the surface triangles, with a Gauss rule of selectable degree on every tet.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <vector>

namespace polycut::basis::detail {

/// A point of a tet rule: barycentric coordinates and a weight as a fraction of the tet volume.
struct TetPoint {
    std::array<double, 4> bary {};
    double weight = 0;
};

/// Positive-weight tet rule exact for total degree <= degree: the centroid (degree <= 1), the
/// 4-point Hammer-Marlowe-Stroud rule (degree 2), else a collapsed (Duffy) Gauss-Legendre
/// product rule with n = ceil((degree + 3) / 2) points per axis.
const std::vector<TetPoint>& tet_rule(int degree);

/// Quadrature points [m] and weights [m^3] of the star tetrahedralization from `apex` over the
/// triangles (node indices into `nodes`). Tets of zero volume are skipped.
void star_rule(const std::vector<Vec3>& nodes, const std::vector<std::array<Index, 3>>& triangles,
    const Vec3& apex, int degree, std::vector<Vec3>& points, std::vector<double>& weights);

} // namespace polycut::basis::detail
