// A mesh in flat arrays: what an undo snapshot keeps. Copying a Mesh allocates one vector per
// face and two per cell (~110k allocations on a 26k-tet organ, ~10 ms); packing it writes a
// handful of contiguous arrays, and unpacking (only when a cut is undone) rebuilds the vectors.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::mesh {

/// Every field of a Mesh, in CSR form (offsets into one array per list).
struct PackedMesh {
    std::vector<Vec3> rest;
    std::vector<Index> face_offset, face_nodes; ///< face f: face_nodes[face_offset[f] ..]
    std::vector<Index> face_owner, face_neighbour, face_parent;
    std::vector<FaceTag> face_tag;
    std::vector<Index> cell_node_offset, cell_nodes, cell_face_offset, cell_faces;
    std::vector<CellShape> cell_shape;
    std::vector<Index> cell_parent;
};

/// Packs `m` into `out` (its arrays are reused: no allocation once they are large enough).
void pack(const Mesh& m, PackedMesh& out);
/// The mesh `p` holds, exactly (unpack(pack(m)) == m field by field).
Mesh unpack(const PackedMesh& p);

} // namespace polycut::mesh
