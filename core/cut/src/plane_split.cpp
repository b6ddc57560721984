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
// The loop closing the open surface made by `loops` (outward for the cell), oriented
// outward for the same cell: each boundary edge (u, v) appears reversed.
std::vector<Index> closing_loop(const std::vector<std::vector<Index>>& loops) {
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
    if (next.size() < 3)
        throw std::logic_error("cut: hole of a split cell has fewer than 3 nodes");
    std::vector<Index> loop;
    Index v = next.begin()->first;
    do {
        loop.push_back(v);
        auto it = next.find(v);
        if (it == next.end() || loop.size() > next.size())
            throw std::logic_error("cut: hole of a split cell is not closed");
        v = it->second;
    } while (v != loop.front());
    if (loop.size() != next.size())
        throw std::logic_error("cut: hole of a split cell has several loops");
    return loop;
}
} // namespace

Index split_cell(Editor& ed, PlaneClassifier& cls, Index c, Index& interface) {
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

    const Index c2 = m.num_cells();
    mesh::Cell child;
    child.parent = c;
    child.shape = mesh::CellShape::Polyhedron;
    m.cells.push_back(std::move(child));
    ed.touch(c2);
    at(m.cells, c).faces = plus_faces;
    at(m.cells, c2).faces = minus_faces;
    for (Index f : minus_faces) {
        mesh::Face& face = at(m.faces, f);
        if (face.owner == c)
            face.owner = c2;
        else if (face.neighbour == c)
            face.neighbour = c2;
    }

    std::vector<std::vector<Index>> loops;
    for (Index f : plus_faces)
        loops.push_back(m.face_loop(f, c));
    mesh::Face iface;
    iface.nodes = closing_loop(loops);
    iface.owner = c;
    iface.neighbour = c2;
    iface.tag = mesh::FaceTag::Interior;
    interface = ed.add_face(std::move(iface));
    ed.refresh_cell_nodes(c);
    ed.refresh_cell_nodes(c2);
    ed.report->new_cells.push_back({ c2, c });
    return c2;
}

} // namespace polycut::cut::detail
