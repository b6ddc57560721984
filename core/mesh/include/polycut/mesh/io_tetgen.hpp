// TetGen volume meshes: a .node file (points) and an .ele file (tetrahedra).
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <string>

namespace polycut::mesh {

/// Reads BASE.node and BASE.ele; `path` is BASE, BASE.node or BASE.ele. Numbering may start at 0
/// or 1 (taken from the first point); point attributes, boundary markers, region attributes,
/// `#` comments and 10-node tets (corners kept) are accepted. Inverted tets are reordered; nodes
/// no tet uses are dropped (file order kept otherwise). Throws FileError(file, line, problem) for
/// a missing or malformed file, a node id out of range, a non-finite coordinate, a zero-volume
/// or repeated tet, or coincident nodes; never returns a partial mesh.
Mesh read_tetgen(const std::string& path);

} // namespace polycut::mesh
