// gmsh .msh volume meshes, ASCII format 2.x and 4.1.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <string>

namespace polycut::mesh {

/// Reads a gmsh ASCII .msh file, format 2.x or 4.1. Keeps 4-node tetrahedra (type 4) and 8-node
/// hexahedra (type 5), in any mix; skips points, lines, triangles and quadrangles, and sections
/// it does not need ($Entities, $PhysicalNames, ...). Inverted tets are reordered; nodes no
/// volume element uses are dropped (file order kept otherwise). Throws FileError(path, line,
/// problem) for a missing file, binary files, versions other than 2.x/4.1, truncated sections,
/// wrong counts, non-numeric or non-finite values, unknown node tags, other 3D element types,
/// zero-volume or inverted hexes, non-planar hex faces (1e-6 relative) and coincident nodes;
/// never returns a partial mesh.
Mesh read_gmsh(const std::string& path);

} // namespace polycut::mesh
