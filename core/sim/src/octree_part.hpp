// Private: the octree of a scene's `"type": "octree"` geometry (issue 15 item 3), and its
// stress-based refinement while the simulation runs (001 sec. 8).
#pragma once

#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/octree.hpp"
#include "polycut/scene/scene.hpp"

#include <memory>

namespace polycut::sim {

/// The implicit shape a geometry names (shape, center, radii, inner_radius, length).
meshing::ImplicitShape implicit_shape(const scene::Geometry& g);

/// The scene's octree, built and balanced (not yet meshed): the object is the implicit shape,
/// the surface file (read with read_surface and its exact signed distance) or the box. Throws
/// SceneError pointing at /geometry/... for bad options, FileError for an unreadable file.
std::unique_ptr<meshing::Octree> make_octree(const scene::Scene& s);

} // namespace polycut::sim
