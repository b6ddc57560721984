// Private state of the face-snapping cutter (002 sec. 3.2): node-to-cell adjacency, per-tet
// sweep/edge marks remembered between triangles, pending selected faces, and the per-call
// bookkeeping from which the CutReport is made (pre-call ids of nodes and cells, interpolation
// weights of new nodes, old rest positions of moved nodes).
#pragma once

#include "cell_grid.hpp"
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace polycut::cut::snap {

template <class V> inline auto& at(V& v, Index i) {
    return v[std::size_t(i)];
}

using Weights = std::vector<std::pair<Index, double>>;

/// Local edges of a tet, as local node pairs; the order of tet_dihedral_angles.
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges { { { 0, 1 }, { 0, 2 }, { 0, 3 },
    { 1, 2 }, { 1, 3 }, { 2, 3 } } };

/// Local face of a tet (index into mesh::kTetFaces) opposite local node k.
inline constexpr std::array<int, 4> kFaceOpposite { 2, 3, 1, 0 };

/// A sweep plane n . x = offset with the triangle it came from.
struct SweepPlane {
    Triangle tri;
    Vec3 normal = Vec3::UnitZ(); ///< unit normal
    double offset = 0; ///< [m]
    geometry::Aabb box; ///< bounds of tri [m]
    double distance(const Vec3& x) const { return normal.dot(x) - offset; }
};

struct State {
    State(mesh::Mesh& mesh, const SnapOptions& options);

    mesh::Mesh& m;
    SnapOptions opt;
    SnapStats stats;
    CutReport* report = nullptr;

    double L = 1; ///< rest bounding-box diagonal [m]
    /// Longest tet edge at the last rebuild() [m]: how far from a triangle a held-back face can
    /// still be affected by it (dissect_pending).
    double max_edge = 0;
    Vec3 center; ///< rest bounding-box centre [m]
    double volume0 = 0; ///< rest volume when bound [m^3] (budget of degeneracy removal)
    /// Rest volume after the last call [m^3]: the next call's volume before (the mesh is
    /// changed only through this cutter between calls; rebuild() after anything else)
    double volume_now = 0;

    std::vector<std::vector<Index>> node_cells;
    /// Per tet and local edge: local node marked as closest to the first sweep crossing, or -1.
    std::vector<std::array<std::int8_t, 6>> marks;
    std::vector<char> selected; ///< per tet: a face was already selected from its marks
    /// Tets whose marks name a face the blade has not swept yet (docs/decisions/0008), retried
    /// after each triangle of the stroke.
    std::vector<Index> deferred;
    std::vector<Index> pending; ///< selected interior faces not dissected yet, in selection order
    /// Rest bounds of the nodes of the faces the last dissect_pending() cut [m] (empty: none):
    /// held-back faces there may have come free (dissect_pending looks at them again).
    geometry::Aabb last_dissected;
    std::vector<Index> near; ///< tets whose bounds overlap the current triangle
    std::vector<SweepPlane> recent; ///< the last triangles of the sweep, newest last
    /// Every triangle of the current sweep (cleared by end_sweep): where the blade has passed,
    /// for deciding that a held-back face lies behind the blade.
    std::vector<SweepPlane> swept;
    /// swept_around()'s answers (snap_dissect.cpp) for a node and clearance: a memo of a
    /// function of (x, r) and `swept`, which only grows until end_sweep() clears both. A yes
    /// stays yes; a no is asked again only of the triangles swept since, and only when one of
    /// them passes near x. Keyed by the edge it was asked for; the key only finds the entry, x
    /// and r must match.
    struct SweptMemo {
        Vec3 x = Vec3::Zero();
        double r = 0;
        std::size_t upto = 0; ///< swept[0, upto) answered for
        bool yes = false;
    };
    mutable std::unordered_map<std::uint64_t, SweptMemo> swept_memo;
    /// SnapStats::sweep_tests of the call, counted by swept_around() (copied into stats by end())
    mutable std::uint64_t sweep_tests = 0;
    std::vector<geometry::Aabb> box; ///< rest bounds per tet
    std::vector<char> box_ok;
    /// Signed rest volume per tet [m^3] as of the last end(): end() recomputes the changed tets
    /// only, so a call's volume check costs what it touched (rebuild_faces() moves the entries
    /// with their tets).
    std::vector<double> cell_volume;
    /// Spatial index of the tets' rest bounds (snap_grid.cpp): the tets a triangle can reach
    /// without a pass over the mesh (issue 12 item 5).
    detail::CellGrid grid;

    // Per-call bookkeeping.
    std::vector<Index> node_old; ///< current node -> id before the call, kNone if new
    std::vector<Index> cell_old; ///< current cell -> id before the call, kNone if new
    std::vector<Index> cell_parent; ///< new cell -> pre-call id of the cell it came from
    std::unordered_map<Index, Weights> new_weights; ///< new node -> weights over pre-call ids
    std::unordered_map<Index, Vec3> moved_from; ///< pre-existing node -> rest before the call
    std::vector<char> changed; ///< per current cell
    /// Cells touch() flagged in this call, in order (may hold cells flagged again, cut off or
    /// unflagged since: changed_cells() filters), so that the passes over the changed cells
    /// cost what the call touched, not the mesh.
    std::vector<Index> changed_list;
    Index touched = 0; ///< cells touched by the call (the budget of SnapCutter::cut)
    std::vector<std::pair<Index, Index>> duplicated;
    std::vector<Index> removed_cells_old, removed_nodes_old;
    bool compacted = false;

    void rebuild();
    void begin(CutReport& r);
    void end();

    const geometry::Aabb& bounds(Index c);
    /// Tets whose rest bounds may overlap b, in increasing id order (a superset: callers test
    /// bounds(c) themselves). Valid until the next call.
    const std::vector<Index>& candidates(const geometry::Aabb& b);
    /// Forgets the grid (tets renumbered).
    void invalidate_grid() { grid.invalidate(); }
    void touch(Index c);
    /// The cells flagged changed, in increasing id order.
    std::vector<Index> changed_cells() const;
    /// Moves node n to X, recording its old position and touching its cells.
    void move_node(Index n, const Vec3& X);
    /// Appends a node with weights over pre-call nodes.
    Index add_node(const Vec3& X, Weights w);
    /// Weights of node n over pre-call nodes.
    Weights weights_of(Index n) const;

    const Vec3& X(Index n) const { return m.rest[std::size_t(n)]; }
    /// Global face of tet c with the node set of its local face lf (kNone if none).
    Index global_face(Index c, int lf) const;
    /// Aspect ratio of tet c with node n moved to Xn (pass kNone for no move).
    double aspect(Index c, Index n = kNone, const Vec3& Xn = Vec3::Zero()) const;
};

/// Signed rest volume of tet c [m^3] from its node list.
double tet_volume(const mesh::Mesh& m, Index c);
/// Total rest volume of a tet mesh [m^3]: the sum of tet_volume() in cell order.
double tet_mesh_volume(const mesh::Mesh& m);

// snap_select.cpp: 002 sec. 3.2.1. Marks the crossings of the triangle and returns the newly
// selected interior faces (appended to pending as well).
std::vector<Index> select_faces(State& s, const SweepPlane& plane);

/// Evaluates the deferred tets again (the swept surface has grown); returns the faces selected.
std::vector<Index> retry_deferred(State& s, const SweepPlane& plane);

/// Marks the edges at freshly snapped nodes (they meet the sweep at the node) and returns the
/// faces this completes.
std::vector<Index> mark_snapped_nodes(
    State& s, const SweepPlane& plane, const std::vector<Index>& nodes);

/// Selects interior faces lying in the triangle (after snapping) whose tets are on opposite sides.
void select_faces_in_plane(State& s, const SweepPlane& plane);

// snap_nodes.cpp: 002 sec. 3.2.2. Snaps the nodes of `faces` onto the sweep plane; returns the
// nodes moved.
std::vector<Index> snap_face_nodes(
    State& s, const SweepPlane& plane, const std::vector<Index>& faces);
/// Snaps `nodes` (any order, duplicates allowed) onto the sweep plane; returns the nodes moved.
std::vector<Index> snap_nodes(State& s, const SweepPlane& plane, std::vector<Index> nodes);

// snap_select.cpp, second part: the stroke as one swept surface (docs/decisions/0008). Selects
// the interior faces whose centroid the triangle sweeps and whose nodes are closest nodes of edges
// crossing its plane, snaps those nodes onto the plane and appends the faces that now separate
// tets on opposite sides to pending; returns the nodes moved.
std::vector<Index> select_swept_faces(State& s, const SweepPlane& plane);

/// Whether x lies on the swept surface of the stroke so far: within eps of the plane of a
/// triangle of State::swept parallel to `plane` and inside it.
bool on_swept_surface(const State& s, const SweepPlane& plane, const Vec3& x);

// snap_dissect.cpp: dissects the pending faces that do not pinch an edge: those the current
// triangle can have freed, or with `everything` all of them (the end of a sweep).
void dissect_pending(State& s, bool everything = false);

/// Cuts pending faces held back at pinched edges where the sweep has passed all around those
/// edges: the edges are split at their midpoints and the faces dissected. With `only`, just the
/// pending faces it holds are looked at (the others keep waiting).
void open_pinches(State& s, bool force = false, const std::unordered_set<Index>* only = nullptr);

/// Duplicates node n once per group of its tets not connected through interior faces at n.
void split_node(State& s, Index n);

// snap_pieces.cpp: 002's closest-node selection on an irregular mesh can enclose a tet or two on
// the far side of the sweep. Drops from `take` the faces that would cut off a piece of fewer than
// SnapOptions::min_piece_cells tets (appending them to `dropped`); returns the pieces kept.
Index keep_small_pieces(State& s, std::unordered_set<Index>& take, std::vector<Index>& dropped);

// snap_degenerate.cpp: 002 sec. 3.2.3. Collapses degenerate tets among the changed cells (or
// among all cells), cuts free what no collapse removes.
void remove_degeneracies(State& s, bool all_cells = false);

} // namespace polycut::cut::snap
