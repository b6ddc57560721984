// Private mesh editing layer of the cutter: node-to-cell adjacency, edge splits applied to every
// face around an edge (so neighbours share the node, DESIGN.md sec. 3), face splits seen by both
// cells, per-cell caches (bounds, thickness) and the bookkeeping of the CutReport.
#pragma once

#include "cell_grid.hpp"
#include "polycut/cut/cut_options.hpp"
#include "polycut/cut/cut_report.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/mesh.hpp"

#include <span>
#include <unordered_map>
#include <vector>

namespace polycut::cut::detail {

template <class V> inline auto& at(V& v, Index i) {
    return v[std::size_t(i)];
}

using Weights = std::vector<std::pair<Index, double>>;

/// A plane n . x = offset with per-node classification (snapped to 0 within eps).
struct Plane {
    Vec3 normal = Vec3::UnitZ(); ///< unit normal
    double offset = 0; ///< [m]
    double distance(const Vec3& x) const { return normal.dot(x) - offset; }
};

/// How far beyond its bounds a cell can be reached by a sweep triangle, in snapping distances
/// times its bounds' diagonal (a cell's thickness is at most twice its diagonal;
/// split_along_triangle).
constexpr double kSweepReach = 2.0;

class Editor {
public:
    Editor(mesh::Mesh& mesh, const CutOptions& options);

    mesh::Mesh& m;
    const CutOptions& opt;

    /// Rebuilds adjacency and caches from scratch.
    void rebuild();
    /// Starts a call: resets the report and its bookkeeping.
    void begin(CutReport& report);
    /// Ends a call: reclassifies changed cells, fills the report's lists.
    void end();

    /// Appends a node at X with flattened interpolation weights.
    Index add_node(const Vec3& X, Weights weights, Index parent_cell, NodeOrigin::Kind kind);
    /// Weights of node n over nodes that existed before the call.
    Weights weights_of(Index n) const;
    /// Creates the node a + t (b - a) and inserts it between a and b in every face around the
    /// edge. Returns the node.
    Index split_edge(Index a, Index b, double t, Index parent_cell);
    /// Splits face f: f keeps loop `keep`, a new face gets loop `other` (same owner, neighbour,
    /// tag; parent f) and is added to both cells. Returns the new face.
    Index split_face(Index f, std::vector<Index> keep, std::vector<Index> other);
    /// Appends a face and registers it with its owner and neighbour.
    Index add_face(mesh::Face face);
    /// Moves node n to rest position X [m] and touches its cells; the first rest position of
    /// the call goes to CutReport::moved_nodes (the undo and the state follow it).
    void move_node(Index n, const Vec3& X);
    /// Replaces the node list of cell c by the union of its face loops and updates adjacency.
    void refresh_cell_nodes(Index c);
    /// Marks cell c changed (invalidates caches).
    void touch(Index c);
    /// After cells were removed and renumbered (cell_map: old id -> new id or kNone): the
    /// per-cell caches move to the new ids (a full rebuild() would recompute every cell's
    /// bounds and thickness in the next scan, O(mesh) per cut), the adjacency is rebuilt and
    /// the change list restarts.
    void renumber(const std::vector<Index>& cell_map);

    /// Cells changed since begin(), in order of first change (grows while iterating).
    const std::vector<Index>& changed_cells() const { return m_changed_list; }

    const geometry::Aabb& bounds(Index c);
    /// Cells below `limit` whose bounds, grown by kSweepReach snapping distances times their
    /// diagonal, may overlap `box`: a superset, in increasing id order (a detail::CellGrid of
    /// the grown bounds, made with the editor and again when CellGrid::stale() says so).
    /// What a sweep triangle can reach without a pass over the mesh (issue 12 item 5: a cut's
    /// work follows what it touches).
    const std::vector<Index>& cells_near(const geometry::Aabb& box, Index limit);
    /// Thickness 6 V / A of cell c [m].
    double thickness(Index c);
    /// Snapping distance of node n [m].
    double snap_eps(Index n);
    /// Cube root of the mean cell volume of the mesh the editor was made for [m] (fixed: the
    /// scale of tolerances that must not shrink as cuts make cells smaller).
    double cell_size() const { return m_cell_size; }

    /// Cells using node n.
    std::vector<std::vector<Index>> node_cells;
    CutReport* report = nullptr;

private:
    std::vector<geometry::Aabb> m_bounds;
    std::vector<double> m_thickness; // NaN when stale
    double m_cell_size = 0;
    std::vector<char> m_bounds_ok;
    std::vector<char> m_changed;
    std::vector<Index> m_changed_list;
    CellGrid m_grid; ///< cells_near()'s
    void build_grid();
};

/// Position of v in loop, or -1.
int find_in(const std::vector<Index>& loop, Index v);

/// Removes the faces with dead[f] != 0 from m.faces and renumbers the cells' face lists and the
/// faces' parents (a removed parent becomes kNone); returns old face id -> new id (kNone if
/// removed). Owners and neighbours are left as they are.
std::vector<Index> compact_faces(mesh::Mesh& m, const std::vector<char>& dead);

/// Signs (-1, 0, +1) of a face loop: cleanly split means the nonzero signs change at most twice
/// around the loop and every zero run between a + and a - arc has length one.
bool clean_pattern(const std::vector<int>& signs);

/// Splits a loop with both signs (after edge nodes were inserted, so + and - never touch) into
/// the part on the + side and the part on the - side; both include the two chord nodes.
void split_loop(const std::vector<Index>& loop, const std::vector<int>& signs,
    std::vector<Index>& plus, std::vector<Index>& minus);

} // namespace polycut::cut::detail
