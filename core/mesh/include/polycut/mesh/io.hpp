// Mesh files: readers for volume meshes (TetGen, gmsh) and writers (VTU, OBJ).
#pragma once

#include "polycut/mesh/io_gmsh.hpp"
#include "polycut/mesh/io_obj.hpp"
#include "polycut/mesh/io_tetgen.hpp"
#include "polycut/mesh/io_vtu.hpp"

namespace polycut::mesh {

/// Reads a volume mesh, choosing the reader by extension: .msh (gmsh), .node or .ele (TetGen,
/// with the other file of the pair next to it). Throws FileError for other extensions and for
/// anything the reader rejects.
Mesh read_volume_mesh(const std::string& path);

} // namespace polycut::mesh
