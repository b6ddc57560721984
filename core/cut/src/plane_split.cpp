#include "plane_split.hpp"

#include "polycut/cut/invariants.hpp"
#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace polycut::cut::detail {

int PlaneClassifier::sign(Index n) {
    auto it = m_sign.find(n);
    if (it != m_sign.end())
        return it->second;
    const double d = distance(n);
    const double eps = std::max(m_min_eps, m_ed.snap_eps(n));
    const int s = d > eps ? 1 : (d < -eps ? -1 : 0);
    m_sign.emplace(n, s);
    return s;
}

namespace {
/// The unit direction node n moves in to reach the cut plane without changing the rest volume:
/// `want` (the plane's normal) for an interior node; `want` projected into the skin where the
/// node's boundary faces are coplanar; along the crease where they lie in two planes; zero (no
/// move) at a corner or where the projection vanishes.
Vec3 volume_keeping_direction(Editor& ed, Index n, const Vec3& want) {
    constexpr double kSamePlane = 1e-6; // |a x b| of unit normals: the same skin plane
    std::vector<Vec3> normals;
    for (Index c : at(ed.node_cells, n))
        for (Index f : at(ed.m.cells, c).faces) {
            const mesh::Face& face = at(ed.m.faces, f);
            if (face.boundary() && find_in(face.nodes, n) >= 0)
                normals.push_back(
                    geometry::polygon_normal(geometry::gather(ed.m.rest, face.nodes)).normalized());
        }
    if (normals.empty())
        return want;
    const Vec3 a = normals.front();
    Vec3 t = want - want.dot(a) * a; // within the first skin plane
    for (const Vec3& b : normals)
        if (a.cross(b).norm() > kSamePlane) {
            t = a.cross(b); // a crease: along it
            break;
        }
    if (t.norm() < 1e-12)
        return Vec3::Zero();
    t.normalize();
    for (const Vec3& b : normals)
        if (std::abs(b.dot(t)) > kSamePlane)
            return Vec3::Zero(); // a corner of the skin
    return t;
}
} // namespace

bool PlaneClassifier::project_onto_plane(Index n) {
    if (sign(n) != 0)
        return false;
    const double d = distance(n);
    if (std::abs(d) <= 1e-12 * m_ed.cell_size())
        return false; // on the plane to round-off already
    // Skin nodes slide in the skin (the rest volume stays), at most twice as far as the plane is.
    const Vec3 t = volume_keeping_direction(m_ed, n, m_plane.normal);
    const double along = t.dot(m_plane.normal);
    if (std::abs(along) < 0.5)
        return false;
    const Vec3 old_rest = at(m_ed.m.rest, n);
    const Vec3 target = old_rest - (d / along) * t;
    // The faces around n tilt by the move: keep it only where no cell around n gets more than
    // kMoveConvexity of its diagonal out of convex (later splits make smaller cells of the
    // tilted faces, and the violation grows with 1 / their size).
    constexpr double kMoveConvexity = 1e-3;
    const auto& cells = at(m_ed.node_cells, n);
    std::vector<double> before(cells.size());
    for (std::size_t k = 0; k < cells.size(); ++k)
        before[k] = convexity_violation(m_ed.m, cells[k]);
    at(m_ed.m.rest, n) = target;
    bool keeps_convex = true;
    for (std::size_t k = 0; k < cells.size() && keeps_convex; ++k)
        keeps_convex = convexity_violation(m_ed.m, cells[k]) <= std::max(before[k], kMoveConvexity);
    at(m_ed.m.rest, n) = old_rest;
    if (!keeps_convex)
        return false;
    m_ed.move_node(n, target);
    return true;
}

std::vector<int> PlaneClassifier::signs(const std::vector<Index>& loop) {
    std::vector<int> s;
    s.reserve(loop.size());
    for (Index n : loop)
        s.push_back(sign(n));
    return s;
}

void PlaneClassifier::split_crossing_edges(Index face, Index parent_cell) {
    // Re-read the loop after each insertion: insertions shift positions.
    for (std::size_t i = 0; i < at(m_ed.m.faces, face).nodes.size(); ++i) {
        const auto& loop = at(m_ed.m.faces, face).nodes;
        const Index a = loop[i], b = loop[(i + 1) % loop.size()];
        const int sa = sign(a), sb = sign(b);
        if (sa * sb >= 0)
            continue;
        const double da = distance(a), db = distance(b);
        // 000 sec. 5.1: the new node is where the plane crosses the edge; linear along edges.
        const double t = da / (da - db);
        const Index mid = m_ed.split_edge(a, b, t, parent_cell);
        set_zero(mid);
    }
}

bool can_split_cell(Editor& ed, PlaneClassifier& cls, Index c) {
    bool plus = false, minus = false;
    for (Index n : at(ed.m.cells, c).nodes) {
        const int s = cls.sign(n);
        plus = plus || s > 0;
        minus = minus || s < 0;
    }
    if (!plus || !minus)
        return false;
    for (Index f : at(ed.m.cells, c).faces) {
        const auto s = cls.signs(at(ed.m.faces, f).nodes);
        if (std::all_of(s.begin(), s.end(), [](int v) { return v == 0; }))
            return false;
        if (!clean_pattern(s))
            return false;
    }
    return true;
}

namespace {
// The loops closing the open surface made by `loops` (outward for the cell), each oriented
// outward for the same cell: each boundary edge (u, v) appears reversed. A convex cell has one;
// a non-convex one (merged cells) may have several, one per place the plane crosses it.
std::vector<std::vector<Index>> closing_loops(const std::vector<std::vector<Index>>& loops) {
    std::map<std::pair<Index, Index>, int> directed;
    for (const auto& l : loops)
        for (std::size_t i = 0; i < l.size(); ++i)
            ++directed[{ l[i], l[(i + 1) % l.size()] }];
    std::map<Index, Index> next;
    for (const auto& [e, count] : directed) {
        if (directed.count({ e.second, e.first }))
            continue;
        // Hole edge (u, v): the closing face walks v -> u.
        if (count != 1 || next.count(e.second))
            throw std::logic_error("cut: hole of a split cell is not a simple loop");
        next[e.second] = e.first;
    }
    std::vector<std::vector<Index>> out;
    std::map<Index, char> used;
    for (const auto& [start, unused] : next) {
        if (used.count(start))
            continue;
        std::vector<Index> loop;
        Index v = start;
        do {
            loop.push_back(v);
            used[v] = 1;
            auto it = next.find(v);
            if (it == next.end() || loop.size() > next.size())
                throw std::logic_error("cut: hole of a split cell is not closed");
            v = it->second;
        } while (v != loop.front());
        if (loop.size() < 3)
            throw std::logic_error("cut: hole of a split cell has fewer than 3 nodes");
        out.push_back(std::move(loop));
    }
    if (out.empty())
        throw std::logic_error("cut: a split cell has no hole");
    return out;
}

/// Groups of faces (indices into `loops`) connected through shared edges.
std::vector<int> components(const std::vector<std::vector<Index>>& loops, int& count) {
    std::vector<int> parent(loops.size());
    for (std::size_t i = 0; i < parent.size(); ++i)
        parent[i] = int(i);
    auto find = [&](int i) {
        while (parent[std::size_t(i)] != i)
            i = parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
        return i;
    };
    std::map<std::pair<Index, Index>, int> first;
    for (std::size_t f = 0; f < loops.size(); ++f)
        for (std::size_t i = 0; i < loops[f].size(); ++i) {
            const auto [it, fresh] = first.emplace(
                std::minmax(loops[f][i], loops[f][(i + 1) % loops[f].size()]), int(f));
            if (!fresh)
                parent[std::size_t(find(int(f)))] = find(it->second);
        }
    std::map<int, int> id;
    std::vector<int> out(loops.size());
    for (std::size_t f = 0; f < loops.size(); ++f)
        out[f] = id.emplace(find(int(f)), int(id.size())).first->second;
    count = int(id.size());
    return out;
}
} // namespace

Index split_cell(Editor& ed, PlaneClassifier& cls, Index c, std::vector<Index>& interfaces) {
    mesh::Mesh& m = ed.m;
    const std::vector<Index> faces = at(m.cells, c).faces;
    for (Index f : faces)
        cls.split_crossing_edges(f, c);

    std::vector<Index> plus_faces, minus_faces;
    for (Index f : faces) {
        const auto loop = at(m.faces, f).nodes;
        const auto s = cls.signs(loop);
        const bool hp = std::find(s.begin(), s.end(), 1) != s.end();
        const bool hm = std::find(s.begin(), s.end(), -1) != s.end();
        if (hp && hm) {
            std::vector<Index> p, q;
            split_loop(loop, s, p, q);
            if (p.size() < 3 || q.size() < 3)
                throw std::logic_error("cut: face split produced a degenerate loop");
            const Index g = ed.split_face(f, std::move(p), std::move(q));
            plus_faces.push_back(f);
            minus_faces.push_back(g);
        } else if (hm) {
            minus_faces.push_back(f);
        } else {
            plus_faces.push_back(f);
        }
    }

    // The holes the plane leaves, and the pieces on each side: one each for a convex cell; a
    // non-convex cell may fall into more (each piece a cell, each hole a face between two).
    std::vector<std::vector<Index>> plus_loops, minus_loops;
    for (Index f : plus_faces)
        plus_loops.push_back(m.face_loop(f, c));
    for (Index f : minus_faces)
        minus_loops.push_back(m.face_loop(f, c));
    const std::vector<std::vector<Index>> holes = closing_loops(plus_loops);
    int n_plus = 0, n_minus = 0;
    const std::vector<int> plus_piece = components(plus_loops, n_plus);
    const std::vector<int> minus_piece = components(minus_loops, n_minus);
    // Piece cells: the first + piece stays c, the others and every - piece are appended.
    std::vector<Index> plus_cell(static_cast<std::size_t>(n_plus));
    std::vector<Index> minus_cell(static_cast<std::size_t>(n_minus));
    auto add_cell = [&]() {
        const Index id = m.num_cells();
        mesh::Cell child;
        child.parent = c;
        child.shape = mesh::CellShape::Polyhedron;
        m.cells.push_back(std::move(child));
        ed.touch(id);
        return id;
    };
    plus_cell[0] = c;
    for (int k = 1; k < n_plus; ++k)
        plus_cell[std::size_t(k)] = add_cell();
    for (int k = 0; k < n_minus; ++k)
        minus_cell[std::size_t(k)] = add_cell();
    const Index first_new = n_plus > 1 ? plus_cell[1] : minus_cell[0];
    for (Index x : plus_cell)
        at(m.cells, x).faces.clear();
    for (Index x : minus_cell)
        at(m.cells, x).faces.clear();
    auto move_face = [&](Index f, Index to) {
        at(m.cells, to).faces.push_back(f);
        if (to == c)
            return;
        mesh::Face& face = at(m.faces, f);
        if (face.owner == c)
            face.owner = to;
        else if (face.neighbour == c)
            face.neighbour = to;
    };
    for (std::size_t i = 0; i < plus_faces.size(); ++i)
        move_face(plus_faces[i], plus_cell[std::size_t(plus_piece[i])]);
    for (std::size_t i = 0; i < minus_faces.size(); ++i)
        move_face(minus_faces[i], minus_cell[std::size_t(minus_piece[i])]);
    // Each hole lies between the + piece and the - piece whose faces have its edges: the hole
    // walks them reversed, so its edge (a, b) is a + face's (b, a).
    std::map<std::pair<Index, Index>, int> plus_edge, minus_edge;
    for (std::size_t i = 0; i < plus_loops.size(); ++i)
        for (std::size_t k = 0; k < plus_loops[i].size(); ++k)
            plus_edge[{ plus_loops[i][k], plus_loops[i][(k + 1) % plus_loops[i].size()] }]
                = plus_piece[i];
    for (std::size_t i = 0; i < minus_loops.size(); ++i)
        for (std::size_t k = 0; k < minus_loops[i].size(); ++k)
            minus_edge[std::minmax(
                minus_loops[i][k], minus_loops[i][(k + 1) % minus_loops[i].size()])]
                = minus_piece[i];
    interfaces.clear();
    for (const std::vector<Index>& hole : holes) {
        const auto p = plus_edge.find({ hole[1], hole[0] });
        const auto q = minus_edge.find(std::minmax(hole[0], hole[1]));
        if (p == plus_edge.end() || q == minus_edge.end())
            throw std::logic_error("cut: a hole of a split cell borders no piece");
        mesh::Face iface;
        iface.nodes = hole;
        iface.owner = plus_cell[std::size_t(p->second)];
        iface.neighbour = minus_cell[std::size_t(q->second)];
        iface.tag = mesh::FaceTag::Interior;
        interfaces.push_back(ed.add_face(std::move(iface))); // into both cells' face lists
    }
    for (Index x : plus_cell)
        ed.refresh_cell_nodes(x);
    for (Index x : minus_cell)
        ed.refresh_cell_nodes(x);
    for (std::size_t k = 1; k < plus_cell.size(); ++k)
        ed.report->new_cells.push_back({ plus_cell[k], c });
    for (Index x : minus_cell)
        ed.report->new_cells.push_back({ x, c });
    return first_new;
}

} // namespace polycut::cut::detail
