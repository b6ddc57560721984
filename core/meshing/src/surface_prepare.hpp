// Private to the meshing module: checking a triangle surface for meshing and orienting it
// outward, and the Alpha_wrap_3 of a soup (CGAL behind a plain interface; each in its own
// translation unit because the CGAL packages compile slowly).
#pragma once

#include "polycut/meshing/surface.hpp"

#include <string>

namespace polycut::meshing::detail {

/// Problems no repair can fix: no triangles, non-finite coordinates, ids out of range. Empty
/// string if none. (A triangle that repeats a vertex is a degenerate face, which repair removes.)
std::string soup_problem(const SurfaceMesh& surface);

/// Checks that the surface is a closed, orientable, self-intersection-free 2-manifold without
/// degenerate (repeated-id) triangles and, if so, orients every component outward (nested
/// components bound the volume between them) and drops unused vertices. Returns the problem,
/// or an empty string on success (surface edited).
std::string prepare_closed_surface(SurfaceMesh& surface);

/// The Alpha_wrap_3 of the triangles of `surface` [m]: a closed, outward-oriented 2-manifold
/// without self-intersections at distance `offset` [m] outside the input, carved by balls of
/// radius `alpha` [m]. Both must be > 0.
SurfaceMesh alpha_wrap(const SurfaceMesh& surface, double alpha, double offset);

/// CGAL Mesh_3 of the volume bounded by a surface that prepare_closed_surface() accepted
/// (surface.cpp). Options must be checked. Reports each phase to `sink` (may be empty).
mesh::Mesh mesh_prepared_surface(
    const SurfaceMesh& surface, const MeshingOptions& options, const ProgressSink& sink = {});

} // namespace polycut::meshing::detail
