// What a cut changed, so the simulation can update its state without popping (000 sec. 5.1):
// new nodes with interpolation weights, new cells with their parent, changed cells, cut faces.
#pragma once

#include "polycut/common/types.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace polycut::cut {

/// Where a new node came from.
struct NodeOrigin {
    enum class Kind : std::uint8_t {
        Edge, ///< on an edge where a plane crossed it
        Pocket, ///< at the centroid of a cut face (000 sec. 5.2)
        Duplicate, ///< a copy of a node separated by the cut
    };
    Index node = kNone; ///< the new node's id
    Kind kind = Kind::Edge;
    Index parent_cell = kNone; ///< a cell (id after the call) whose interpolant covers the node
    /// Interpolation weights over nodes that existed before the call (ids < nodes_before); they
    /// sum to 1 and reproduce the rest position. Displacement and velocity of the new node are
    /// the same weighted sums (linear along edges and in faces of convex cells).
    std::vector<std::pair<Index, double>> weights;
};

/// A cell made by the call.
struct CellOrigin {
    Index cell = kNone; ///< new cell id
    Index parent = kNone; ///< cell it was split from (id before the call)
};

/// Everything a cut call changed. Cell and node ids only grow during a call, except cells
/// removed by sliver merging (then `cell_map` renumbers).
struct CutReport {
    Index nodes_before = 0, nodes_after = 0; ///< node counts
    Index cells_before = 0, cells_after = 0; ///< cell counts
    Index faces_before = 0; ///< face count at the start of the call
    double volume_before = 0, volume_after = 0; ///< total rest volume [m^3]
    std::vector<NodeOrigin> new_nodes; ///< in creation order, ids nodes_before...
    std::vector<std::pair<Index, Index>> duplicated; ///< (original node, copy)
    std::vector<CellOrigin> new_cells; ///< cells appended by splits
    /// Cells whose nodes, faces or geometry changed (ids after the call, sorted): they need a new
    /// basis, quadrature and Ke, once, at the end of the tick (000 sec. 5.1). Includes new cells.
    std::vector<Index> changed_cells;
    /// Old cell id -> new id (kNone if merged away); empty when no cell was removed.
    std::vector<Index> cell_map;
    std::vector<Index> removed_cells; ///< old ids of cells merged away by sliver removal
    /// Faces tagged Cut by this call (both sides; a face that grew by merging with one counts)
    std::vector<Index> cut_faces;
    Index pockets = 0; ///< pocket nodes inserted (each counted once per side)
    Index slivers_merged = 0; ///< cells removed by sliver merging
    /// Cut faces merged into a coplanar Cut face of the same cell (face ids then renumbered)
    Index cut_faces_merged = 0;
    Index nodes_coarsened = 0; ///< collinear nodes taken out of the changed cells' faces
    Index slivers_kept = 0; ///< slivers left because no merge with a neighbour stayed convex
    Index cells_skipped = 0; ///< crossed cells left unsplit (degenerate configuration)
    Index triangles = 0; ///< sweep triangles processed
    Index triangles_missed = 0; ///< triangles that touched no cell (no change)
    bool topology_changed = false; ///< any node, face or cell changed
    /// The face table was compacted or rebuilt (sliver merges, merged cut faces, face
    /// snapping's degeneracy removal): face ids before and after the call do not correspond.
    bool faces_renumbered = false;
    /// When merged cut faces were the call's only compaction (cell splitting): face id before
    /// the call -> id after it (kNone: merged away), over the faces that existed before the
    /// call; faces the call appended are not in it. Empty otherwise. The undo journal moves its
    /// mirror's faces along it instead of copying the whole mesh.
    std::vector<Index> face_map;
    /// The stiffness sparsity pattern changed (new nodes or new node pairs in a cell); the solver
    /// must re-analyse.
    bool pattern_changed = false;
    double elapsed_ms = 0; ///< wall time of the call [ms]
    /// Cell splitting: the cells the call changed in tet equivalents, each weighted by the
    /// square of its face corners / 12 (a tet 1; a polyhedron of 40 corners, what a cell
    /// re-cut by many small triangles becomes, 11.1). The model update after a cut (mean value
    /// integration and stiffness of the changed cells) grows so: on the default block it was
    /// 0.04-0.05 ms per unit, r = 0.96-0.99 over curved and random strokes, where the plain
    /// count of changed cells did not predict it. What the per-tick cut budget counts.
    /// Face snapping: the cells the call touched plus its pinch and swept-around tests, in the
    /// same units (kPinchChecksPerWork, kSweepTestsPerWork in snap_cutter.hpp).
    double work = 0;
    /// Face snapping (`tet`) only: old node id -> new id (kNone if collapsed away); empty when
    /// no node was removed. Ids in `new_nodes`, `duplicated` and `moved_nodes` are after the call;
    /// NodeOrigin weights refer to ids before it.
    std::vector<Index> node_map;
    std::vector<Index> removed_nodes; ///< `tet` only: old ids of nodes removed by edge collapses
    /// (node id after the call, rest position before the call [m]) of every existing node whose
    /// rest position the cut moved: face snapping (onto the sweep, collapses) and cell
    /// splitting (a node snapped onto a sweep triangle's plane moves onto it, decision 0057).
    std::vector<std::pair<Index, Vec3>> moved_nodes;
};

} // namespace polycut::cut
