// Structured meshes of a box: hexahedra, or hexahedra split into tetrahedra.
#pragma once

#include "polycut/mesh/mesh.hpp"

namespace polycut::mesh {

/// A box [lo, hi] divided into cells.x * cells.y * cells.z hexahedral blocks.
struct BoxGrid {
    Vec3 lo = Vec3::Zero(); ///< min corner [m]
    Vec3 hi = Vec3::Ones(); ///< max corner [m]
    Eigen::Vector3i cells { 1, 1, 1 }; ///< blocks along x, y, z (each >= 1)
};

/// How a hexahedral block is split into tetrahedra.
enum class TetSplit {
    Kuhn6, ///< 6 tets around the main diagonal (node 0 to node 6); conforming across blocks
    Five, ///< 5 tets, alternating orientation by block parity so faces conform
};

/// Grid nodes are numbered i + (nx+1) (j + (ny+1) k).
Mesh hex_grid(const BoxGrid& grid);
Mesh tet_grid(const BoxGrid& grid, TetSplit split = TetSplit::Kuhn6);

/// hex_grid() with random groups of face-adjacent blocks merged into single polyhedral cells
/// (issue 4 item 3): about merge_fraction of the blocks end up in merged cells, half of the
/// groups pairs (elongated 12-node boxes, convex) and half L-shaped triples (16 nodes,
/// non-convex). Faces between a merged cell and its neighbours stay the blocks' quads, so the
/// mesh conforms; unmerged blocks stay Hex. Deterministic for a seed; the result is validated.
/// Throws InputError for merge_fraction outside [0, 1] or an empty grid.
Mesh merged_hex_grid(const BoxGrid& grid, double merge_fraction, unsigned seed);

/// Node index of grid point (i, j, k).
inline Index grid_node(const BoxGrid& g, int i, int j, int k) {
    return Index(i + (g.cells.x() + 1) * (j + (g.cells.y() + 1) * k));
}

} // namespace polycut::mesh
