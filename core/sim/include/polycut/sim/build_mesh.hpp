// Builds the mesh a scene's geometry names (box grid, random-plane polyhedra, CGAL meshing of an
// implicit shape or a surface file, or a volume mesh file).
#pragma once

#include "polycut/mesh/mesh.hpp"
#include "polycut/scene/scene.hpp"

namespace polycut::sim {

struct MeshingSummary; // simulation.hpp

/// Throws SceneError (pointing at /geometry/...), FileError or MeshError. CGAL-meshed geometry
/// (surface_file, implicit) writes one progress line per phase to stderr and, if `summary` is
/// given, its repair report and tet quality there (summary->meshed false for other geometry).
mesh::Mesh build_mesh(const scene::Scene& scene, MeshingSummary* summary = nullptr);

} // namespace polycut::sim
