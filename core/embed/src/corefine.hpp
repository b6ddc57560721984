// Private: the CGAL half of splitting an embedded surface along a cut (split.cpp). A patch of the
// surface and the cut's triangles are corefined (CGAL::Polygon_mesh_processing::corefine, exact
// constructions), so that afterwards no triangle of either crosses the other: every crossing is
// an edge of both, at the same double coordinates.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace polycut::embed::detail {

/// A triangle soup with shared vertices.
struct TriangleSet {
    std::vector<Vec3> points; ///< [m]
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// Output only: the input triangle each output triangle lies in.
    std::vector<std::uint32_t> origin;
};

/// What corefine_patch() gives back.
struct Corefined {
    /// The patch refined: its input vertices keep their indices (0 .. #input - 1), new ones follow.
    /// Points within the welding tolerance of each other (in either mesh) are one vertex at one
    /// position in both (the others are left unused, the triangles that collapse between them
    /// dropped); the patch's input vertices keep their positions.
    TriangleSet patch;
    /// The cut refined: its input vertices keep their indices, new ones follow.
    TriangleSet cut;
    /// Edges (vertex pairs, smaller first) of the refined patch that are constrained: on the
    /// intersection with the cut, or pieces of an input constraint.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> constrained;
};

/// Corefines `patch` (a manifold triangle patch, possibly with a border) with `cut` (triangles
/// of the cut surface, possibly with a border); `constrained` are edges of the patch (vertex
/// pairs) to keep marked; `tol` [m] is the welding tolerance of the output (rounding: exact
/// crossings a rounding apart are one point). Throws polycut::Error if CGAL cannot (a
/// self-intersecting input).
Corefined corefine_patch(const TriangleSet& patch, const TriangleSet& cut,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& constrained, double tol);

} // namespace polycut::embed::detail
