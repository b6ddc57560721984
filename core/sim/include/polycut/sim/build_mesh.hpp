// Builds the mesh a scene's geometry names (box grid, random-plane polyhedra, CGAL meshing of an
// implicit shape or a surface file, or a volume mesh file).
#pragma once

#include "polycut/mesh/mesh.hpp"
#include "polycut/scene/scene.hpp"

namespace polycut::sim {

/// Throws SceneError (pointing at /geometry/...), FileError or MeshError.
mesh::Mesh build_mesh(const scene::Scene& scene);

} // namespace polycut::sim
