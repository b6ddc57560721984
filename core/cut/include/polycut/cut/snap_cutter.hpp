// The face-snapping cutter of the `tet` method (seed 002 sec. 3.2-3.3): on a pure tetrahedral
// mesh, each sweep triangle marks, on every edge it crosses, the edge node closest to the
// crossing; a tet whose marks reach three nodes selects that face; the selected faces' nodes snap
// onto the sweep plane (boundary nodes only within their boundary faces); the mesh is dissected
// along the selected faces (nodes duplicated where the cells around them fell apart); finally flat
// tets (needle, spindle, sliver, cap) are collapsed. The cell count stays constant except for
// degeneracy removal and the rare split of an edge where the selected faces pinch it behind the
// sweep.
//
// Mutation contract: a call moves rest positions of the nodes it lists in CutReport::moved_nodes,
// appends nodes (duplicates, edge/face nodes of degeneracy removal and of pinch splits), appends
// Cut faces and rewrites node ids inside cells and faces. Without degeneracy removal and pinch
// splits node, cell and face ids stay valid. When a degenerate tet is collapsed or an edge split,
// cells and nodes are compacted (CutReport::cell_map, CutReport::node_map when something was
// removed) and the face table is rebuilt (face ids renumbered). Invalid input throws InputError
// before anything changes.
#pragma once

#include "polycut/cut/cut_options.hpp"
#include "polycut/cut/cut_report.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <memory>
#include <numbers>
#include <span>

namespace polycut::cut {

/// Options of the face-snapping cutter. Tolerances are relative (dimensionless) unless a unit is
/// given.
struct SnapOptions {
    /// A node closer than plane_eps * L to a sweep plane lies on it (L: rest bounding-box
    /// diagonal of the mesh).
    double plane_eps = 1e-9;
    /// Snap the selected faces' nodes onto the sweep (002 sec. 3.2.2); false gives the jagged
    /// cut of 002 Fig. 3.5.
    bool snap_nodes = true;
    /// A node move is refused when a tet around the node would get an aspect ratio below this
    /// (or a non-positive volume): a guard against inverted and completely flat tets; flat tets
    /// above it are left to degeneracy removal.
    double snap_min_aspect = 1e-3;
    /// Remove degenerate tets after each sweep triangle (002 sec. 3.2.3).
    bool remove_degeneracies = true;
    /// A tet is degenerate when its aspect ratio (min height / max edge) is below this (002: 0.01).
    double degenerate_aspect = 0.01;
    /// A dihedral angle larger than this [rad] is "large" (002: 0.99 pi); the count of large
    /// angles classifies a degenerate tet as needle (0), spindle (1), sliver (2) or cap (3+).
    double large_dihedral = 0.99 * std::numbers::pi;
    /// Collapse passes over the list of degeneracies; a pass that shortens the list is repeated
    /// (002 sec. 3.2.3).
    int max_passes = 8;
    /// A collapse that moves the boundary is refused when the total rest volume would differ
    /// from the volume at binding by more than this fraction (issue 5: below 1e-3).
    double max_volume_change = 5e-4;
    /// A sweep triangle whose area is below min_area * L^2, or whose shortest altitude is below
    /// min_area * L, is rejected as degenerate.
    double min_area = 1e-10;
    /// Triangle corners farther than max_extent * L from the mesh's bounding-box centre are
    /// rejected.
    double max_extent = 1e3;
    /// Cut degenerate tets that no collapse removes free and delete them (002 sec. 3.2.3), if
    /// the volume budget allows; otherwise they are only counted (SnapStats::degenerate_left).
    bool cut_free = true;
    /// A dissection that would enclose a piece of fewer than this many tets (a tet left on the
    /// far side of a jagged cut where a snap was refused, touching its side only at a node) does
    /// not cut those faces: the piece stays with the tets across them. 0 disables the check.
    Index min_piece_cells = 8;
    /// A selected face held back because cutting it would pinch an edge is cut (the edge split
    /// at its midpoint) once the sweep has passed all around the edge's end nodes within this
    /// fraction of the longest edge of the tets around the edge: the incision then lags the
    /// blade by about that distance instead of waiting for nodes that never separate.
    double pinch_clearance = 1.0;
};

/// A face-snapping call's work (CutReport::work, what the per-tick cut budget counts, in units
/// of ~0.045 ms as decision 0066 calibrated cell splitting's) is its touched cells plus its pinch
/// checks (SnapStats::pinch_checks) over kPinchChecksPerWork plus its tests of whether the sweep
/// has passed all around a node (SnapStats::sweep_tests) over kSweepTestsPerWork: a least-squares
/// fit of the calls of a 2,000-triangle random soup through the default block (247 calls, r =
/// 0.98) gave 3.8 us per pinch check and 17 ns per sweep test, the touched cells and triangles
/// next to nothing.
inline constexpr Index kPinchChecksPerWork = 12;
inline constexpr Index kSweepTestsPerWork = 2600;

/// What the last cut call of a SnapCutter did beyond the common CutReport.
struct SnapStats {
    Index edges_crossed = 0; ///< sweep/edge intersections found (first per edge and tet)
    Index faces_selected = 0; ///< faces selected by closest nodes (002 sec. 3.2.1)
    Index faces_dissected = 0; ///< selected faces turned into pairs of Cut faces
    Index faces_pending = 0; ///< selected faces held back (would pinch an edge); retried later
    /// Pinched edges split at their midpoints to cut held-back faces where the sweep has passed
    /// all around them (the pinch would not resolve by itself).
    Index pinches_split = 0;
    /// Edges tested for a pinch (each groups the tets around the edge, and those around its two
    /// nodes when the ring falls apart): the held-back faces' edges are tested again after every
    /// sweep triangle, the cost that grows with a random soup's pending faces (the call's work,
    /// CutReport::work, counts kPinchChecksPerWork of them as one unit)
    Index pinch_checks = 0;
    /// Tests of a point against a sweep triangle (a box test or more) by the checks whether the
    /// sweep has passed all around a pinched edge's nodes: they scan the whole sweep, which on a
    /// random soup of large triangles costs more than the pinch checks. (The centroid test of a
    /// selected face scans it too, but with a box test that costs a few ns: not counted, or a
    /// long organ stroke's ~2,000 deferred tets would count as work they do not cost.)
    std::uint64_t sweep_tests = 0;
    Index nodes_snapped = 0; ///< node moves onto a sweep plane
    Index snaps_refused = 0; ///< node moves refused by the snap_min_aspect guard
    /// Degenerate tets found (first pass of each triangle): aspect ratio below
    /// degenerate_aspect or a dihedral angle above large_dihedral.
    Index degenerate_found = 0;
    Index needles = 0, spindles = 0, slivers = 0, caps = 0; ///< classification of those
    Index edges_collapsed = 0; ///< edge collapses done
    Index edges_split = 0; ///< edge splits done (spindles and slivers)
    Index faces_split = 0; ///< face splits done (caps)
    /// Degenerate tets removed by each path of 002 sec. 3.2.3 (classified when removed): needle
    /// (shortest edge collapsed), spindle (opposite edge split, collapsed), sliver (both
    /// large-angle edges split, collapsed), cap (opposite face split, collapsed).
    Index needles_removed = 0, spindles_removed = 0, slivers_removed = 0, caps_removed = 0;
    /// Incollapsible degenerate tets cut free and deleted after the last pass (002 sec. 3.2.3);
    /// their faces become Cut faces of their neighbours.
    Index cut_free = 0;
    /// Degenerate tets left (neither collapsible nor removable; still positive volume).
    Index degenerate_left = 0;
    /// Newly enclosed pieces of fewer than min_piece_cells tets that were glued back instead of
    /// being cut off (see SnapOptions::min_piece_cells).
    Index islands_merged = 0;
    double volume_change = 0; ///< |V_after - V_before| / V_before of the call
    /// Face tables made again after an edit of the degeneracy-removal model: for the changed
    /// tets only (decision 0016), or whole (a tet deleted or a node orphaned: compaction).
    Index face_tables_local = 0;
    Index face_tables_whole = 0;
};

/// Stateful face-snapping cutter on a tetrahedral mesh it does not own. Between calls it keeps
/// the sweep/edge intersections of tets whose cut is incomplete (002 sec. 3.2.1, Fig. 3.4), so the
/// triangles of one sweep give one connected cut even across calls.
class SnapCutter {
public:
    /// Binds to `mesh` (must outlive the cutter; every cell a Tet). Throws InputError otherwise.
    explicit SnapCutter(mesh::Mesh& mesh, SnapOptions options = {});
    ~SnapCutter();
    SnapCutter(const SnapCutter&) = delete;
    SnapCutter& operator=(const SnapCutter&) = delete;

    /// Cuts along sweep triangles given in REST space [m], in time order. Throws InputError
    /// (mesh unchanged) if a triangle has a non-finite coordinate, is degenerate or lies absurdly
    /// far away. The report lists new nodes (duplicates with weight 1 on their original, edge and
    /// face nodes of degeneracy removal with their interpolation weights), moved nodes, changed
    /// cells, Cut faces, removed cells/nodes with the id maps, and the rest volume before/after.
    /// With `max_changed_cells` > 0 the call stops after the first triangle that brings the
    /// cells it changed to that many (CutReport::triangles says how many were cut).
    CutReport cut(std::span<const Triangle> rest_triangles, Index max_changed_cells = 0);

    /// Forgets the remembered intersections and pending faces (the next sweep starts afresh).
    void end_sweep();
    /// Ends the sweep like end_sweep(), but first cuts the faces still held back because they
    /// would pinch an edge (splitting those edges at their midpoints, as for faces the sweep has
    /// passed all around): when the blade is lifted, what it swept is cut. Same report and
    /// contract as cut().
    CutReport finish_sweep();
    /// Recomputes adjacency after external edits of the mesh (also forgets the sweep).
    void rebuild();
    /// Removes degenerate tets anywhere in the mesh (002 sec. 3.2.3), not only those a cut
    /// changed: e.g. slivers of a Delaunay mesh before the first cut. Same report and id maps as
    /// cut(); stats() tells which paths ran. Forgets the sweep if anything changed.
    CutReport remove_degeneracies();

    /// Statistics of the last cut() call.
    const SnapStats& stats() const;
    const SnapOptions& options() const;
    const mesh::Mesh& mesh() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Aspect ratio of a tet: minimum height over maximum edge length (002 sec. 3.2.3); 0 for a flat
/// tet, sqrt(2/3) for the regular one. Negative for a negatively oriented tet.
double tet_aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Interior dihedral angles [rad] of a tet at its six edges, in the order (0,1), (0,2), (0,3),
/// (1,2), (1,3), (2,3).
std::array<double, 6> tet_dihedral_angles(
    const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

} // namespace polycut::cut
