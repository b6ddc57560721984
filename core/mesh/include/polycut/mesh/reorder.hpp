// Node and cell numbering for memory locality (issue 18). CGAL and other mesh generators number
// nodes in insertion order, so the nodes of one tet are scattered over the whole array: every
// gather of positions, every scatter into the stiffness matrix and every sweep of the solver
// misses the cache, and a range of nodes is no region of the body. Reverse Cuthill-McKee
// (Boost.Graph) numbers neighbours close together (a banded matrix); cells are then ordered by
// their nodes, so consecutive cells share nodes and a range of nodes is a slab of the body.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::mesh {

/// Reverse Cuthill-McKee order of the node graph (nodes adjacent when they share a cell), each
/// connected component from a pseudo-peripheral node (Boost's cuthill_mckee_ordering).
/// Returns new_of_old (#N): node i gets number new_of_old[i]. Nodes of no cell come last, in
/// their old order. Deterministic.
std::vector<Index> rcm_node_order(const Mesh& m);

/// Renumbers nodes in place (node i becomes new_of_old[i], a permutation of 0..#N-1): rest
/// positions, cell node lists (local order kept, so VTK orders and orientations hold) and face
/// loops. Throws InputError if new_of_old is not a permutation.
void renumber_nodes(Mesh& m, const std::vector<Index>& new_of_old);

/// Orders cells by (smallest node, then the other nodes) in place, stable; face owner and
/// neighbour ids and cell parents follow. Face ids are unchanged.
void sort_cells_by_nodes(Mesh& m);

/// rcm_node_order() + renumber_nodes() + sort_cells_by_nodes(): the locality order applied once
/// after meshing. Returns new_of_old.
std::vector<Index> reorder_for_locality(Mesh& m);

/// Largest |i - j| over node pairs sharing a cell (the node graph's bandwidth).
Index node_bandwidth(const Mesh& m);

} // namespace polycut::mesh
