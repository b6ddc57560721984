// Private: turns the nodes and volume elements a reader parsed into a validated Mesh, mapping
// every defect back to the file line it came from.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <array>
#include <string>
#include <vector>

namespace polycut::mesh::io {

/// A tetrahedron (count 4) or hexahedron (count 8) as read, in gmsh/VTK node order, with node
/// numbers into RawMesh::nodes.
struct RawElement {
    std::array<Index, 8> nodes {};
    int count = 4;
    long line = 0; ///< line in RawMesh::element_path
};

/// Everything a reader parsed, before any checking of the geometry.
struct RawMesh {
    std::string node_path; ///< file the nodes were read from
    std::string element_path; ///< file the elements were read from
    std::vector<Vec3> nodes; ///< positions [m]
    std::vector<long> node_lines; ///< line of each node in node_path
    std::vector<RawElement> elements;
};

/// Checks the elements (distinct nodes, non-zero volume, hexes not inverted, no duplicates),
/// reorders inverted tets, drops nodes no element uses, builds the mesh and validates it
/// (planarity 1e-6 relative, duplicate nodes). Throws FileError pointing at the line of the
/// offending element or node.
Mesh build_mesh(const RawMesh& raw);

} // namespace polycut::mesh::io
