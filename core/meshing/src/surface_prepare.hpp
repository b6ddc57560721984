// Private to the meshing module: checking a triangle surface for meshing and orienting it
// outward (CGAL Polygon_mesh_processing behind a plain interface).
#pragma once

#include "polycut/meshing/surface.hpp"

#include <string>

namespace polycut::meshing::detail {

/// Problems any triangle soup can have: non-finite coordinates, ids out of range, repeated ids
/// in a triangle, no triangles. Empty string if none.
std::string soup_problem(const SurfaceMesh& surface);

/// Checks that the surface is a closed, orientable, self-intersection-free 2-manifold and, if
/// so, orients every component outward (nested components bound the volume between them) and
/// drops unused vertices. Returns the problem, or an empty string on success (surface edited).
std::string prepare_closed_surface(SurfaceMesh& surface);

} // namespace polycut::meshing::detail
