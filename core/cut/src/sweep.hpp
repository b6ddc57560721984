// Private: one sweep polygon's cut (000 sec. 5.2) in rest space, and the separation of the
// material along the faces it covers.
#pragma once

#include "editor.hpp"

namespace polycut::cut::detail {

/// Splits every cell the triangle covers along its plane and splits the faces lying in the plane
/// along the triangle's edges. Returns the interior faces inside the triangle (still Interior).
std::vector<Index> split_along_triangle(Editor& ed, const Triangle& tri);

/// Turns the given interior faces into pairs of Cut boundary faces, duplicates the nodes whose
/// cells are no longer connected around them, and inserts a pocket node when nothing opened.
void separate(Editor& ed, const std::vector<Index>& crack);

/// Removes from every face loop the nodes of `cells` that lie strictly inside a straight edge in
/// every face using them (left behind by earlier crack fronts); faces, cells, volume and surface
/// keep their shape. Returns the number of nodes taken out (they stay in the node table, unused).
Index remove_collinear_nodes(Editor& ed, const std::vector<Index>& cells);

/// Merges, in each of `cells`, Cut boundary faces that lie in one plane (to round-off), share one
/// chain of edges and whose union is a convex polygon; the chain's interior nodes leave the cell
/// (only if no other face uses them). Compacts the face table (renumbers the cells' face lists,
/// face parents and CutReport::cut_faces). Returns the number of faces merged away.
Index merge_cut_faces(Editor& ed, const std::vector<Index>& cells);

/// Merges the cells a call left with less than CutOptions::sliver_volume of the volume of their
/// largest interior neighbour into the neighbour whose union with them stays convex (000 sec. 4);
/// compacts cells and faces and fills CutReport::{cell_map, removed_cells, slivers_merged}.
void merge_slivers(Editor& ed);

/// Splits edges still shared by cells that a cut separated around them (non-manifold boundary
/// edges), at their midpoints, and separates the midpoints. Looks at the changed cells only.
void fix_pinched_edges(Editor& ed);

} // namespace polycut::cut::detail
