// Private: splitting convex cells and their faces along a plane (000 sec. 5.1), with nodes
// snapped onto the plane within their snapping distance, edge nodes shared by all cells around
// an edge, and the interface face between the two halves.
#pragma once

#include "editor.hpp"

#include <unordered_map>

namespace polycut::cut::detail {

/// Classification of nodes against one plane during one operation.
class PlaneClassifier {
public:
    /// `min_eps` [m]: the snapping distance is at least this (0: the node's own, Editor::snap_eps).
    PlaneClassifier(Editor& editor, const Plane& plane, double min_eps = 0)
        : m_ed(editor)
        , m_plane(plane)
        , m_min_eps(min_eps) { }
    const Plane& plane() const { return m_plane; }
    /// Signed distance of node n [m].
    double distance(Index n) const { return m_plane.distance(at(m_ed.m.rest, n)); }
    /// -1, 0 (within the node's snapping distance), +1. Cached.
    int sign(Index n);
    /// Forces node n onto the plane (used for nodes created on it).
    void set_zero(Index n) { m_sign[n] = 0; }
    /// Signs of a loop.
    std::vector<int> signs(const std::vector<Index>& loop);
    /// Moves node n, classified on the plane (sign 0) but off it by up to its snapping
    /// distance, onto the plane in rest space (decision 0057), so that the next triangle of a
    /// stroke in the same plane finds it there whatever its snapping distance has become.
    /// Interior nodes move along the plane's normal; skin nodes slide within a flat skin or
    /// along a crease (the rest volume stays), never at a corner. A move that would take a cell
    /// around n out of convex is not made. Returns whether n moved.
    bool project_onto_plane(Index n);
    /// Inserts edge nodes where a loop goes from + to - directly (every face around the edge
    /// gets them). `parent_cell` is recorded as the origin.
    void split_crossing_edges(Index face, Index parent_cell);

private:
    Editor& m_ed;
    Plane m_plane;
    double m_min_eps = 0;
    std::unordered_map<Index, int> m_sign;
};

/// Whether cell c can be split cleanly by the plane: nodes on both sides, every face's sign
/// pattern clean, no face lying in the plane.
bool can_split_cell(Editor& ed, PlaneClassifier& cls, Index c);

/// Splits cell c (which can_split_cell accepted): inserts edge nodes, splits crossed faces for
/// both of their cells, keeps the + part as c and appends the - part. A non-convex cell that
/// the plane crosses in several places falls into more pieces: c keeps the first + piece, the
/// others are appended (each a child of c). Returns the first appended cell; `interfaces`
/// receives the faces between the pieces (owner a + piece), one per hole the plane leaves.
Index split_cell(Editor& ed, PlaneClassifier& cls, Index c, std::vector<Index>& interfaces);

} // namespace polycut::cut::detail
