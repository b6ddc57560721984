// Separation along crack faces (000 sec. 5.2, Fig. 8 d): each covered interior face becomes two
// Cut boundary faces, one per side; a node is duplicated once per group of its cells that are no
// longer connected through interior faces around it (so nodes at the crack front stay shared and
// the cut surface closes there); a pocket node opens a cut that covers no separable node.
#include "polycut/geometry/polygon.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <map>
#include <numeric>

namespace polycut::cut::detail {
namespace {
// Interpolation weights of the area centroid of a loop (as geometry::polygon_centroid:
// fan around the vertex mean).
std::vector<double> centroid_weights(const std::vector<Vec3>& p) {
    const std::size_t k = p.size();
    Vec3 mean = Vec3::Zero();
    for (const Vec3& x : p)
        mean += x;
    mean /= double(k);
    const Vec3 n = geometry::polygon_normal(p);
    std::vector<double> tri(k);
    double total = 0;
    for (std::size_t i = 0; i < k; ++i) {
        tri[i] = 0.5 * (p[i] - mean).cross(p[(i + 1) % k] - mean).dot(n);
        total += tri[i];
    }
    std::vector<double> w(k, 1.0 / double(k));
    if (total <= 0)
        return w;
    for (std::size_t i = 0; i < k; ++i)
        w[i] = total / (3.0 * double(k)) + (tri[i] + tri[(i + k - 1) % k]) / 3.0;
    for (double& x : w)
        x /= total;
    return w;
}

void replace_node(std::vector<Index>& v, Index from, Index to) {
    std::replace(v.begin(), v.end(), from, to);
}

// Duplicates node n once per group of its cells not connected through interior faces that
// contain n. Returns whether it was duplicated.
bool split_node(Editor& ed, Index n) {
    mesh::Mesh& m = ed.m;
    const std::vector<Index> cells = at(ed.node_cells, n);
    if (cells.size() < 2)
        return false;
    std::vector<std::size_t> parent(cells.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::size_t a) {
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        return a;
    };
    auto slot = [&](Index c) {
        return std::size_t(std::find(cells.begin(), cells.end(), c) - cells.begin());
    };
    for (std::size_t i = 0; i < cells.size(); ++i)
        for (Index f : at(m.cells, cells[i]).faces) {
            const mesh::Face& face = at(m.faces, f);
            if (face.boundary() || find_in(face.nodes, n) < 0)
                continue;
            const std::size_t a = slot(face.owner), b = slot(face.neighbour);
            if (a < cells.size() && b < cells.size())
                parent[find(a)] = find(b);
        }
    std::map<std::size_t, std::vector<Index>> groups;
    for (std::size_t i = 0; i < cells.size(); ++i)
        groups[find(i)].push_back(cells[i]);
    if (groups.size() < 2)
        return false;
    // The group with the smallest cell keeps n: deterministic.
    std::vector<std::vector<Index>> ordered;
    for (auto& [root, g] : groups) {
        std::sort(g.begin(), g.end());
        ordered.push_back(g);
    }
    std::sort(ordered.begin(), ordered.end());
    at(ed.node_cells, n) = ordered.front();
    for (std::size_t gi = 1; gi < ordered.size(); ++gi) {
        const auto& g = ordered[gi];
        const Index copy
            = ed.add_node(at(m.rest, n), ed.weights_of(n), g.front(), NodeOrigin::Kind::Duplicate);
        ed.report->duplicated.emplace_back(n, copy);
        at(ed.node_cells, copy) = g;
        for (Index c : g) {
            replace_node(at(m.cells, c).nodes, n, copy);
            for (Index f : at(m.cells, c).faces)
                replace_node(at(m.faces, f).nodes, n, copy);
            ed.touch(c);
        }
    }
    return true;
}

// Whether the cells around edge (a, b) fall apart into several groups when connected only
// through interior faces that contain the edge.
bool ring_disconnected(Editor& ed, Index a, Index b) {
    const mesh::Mesh& m = ed.m;
    auto has_edge = [&](const std::vector<Index>& loop) {
        const int i = find_in(loop, a);
        if (i < 0)
            return false;
        const std::size_t k = loop.size();
        return loop[(std::size_t(i) + 1) % k] == b || loop[(std::size_t(i) + k - 1) % k] == b;
    };
    std::vector<Index> ring;
    for (Index c : at(ed.node_cells, a)) {
        const auto& cb = at(ed.node_cells, b);
        if (std::find(cb.begin(), cb.end(), c) == cb.end())
            continue;
        for (Index f : at(m.cells, c).faces)
            if (has_edge(at(m.faces, f).nodes)) {
                ring.push_back(c);
                break;
            }
    }
    if (ring.size() < 2)
        return false;
    std::vector<char> seen(ring.size(), 0);
    std::vector<std::size_t> stack { 0 };
    seen[0] = 1;
    std::size_t reached = 1;
    while (!stack.empty()) {
        const Index c = ring[stack.back()];
        stack.pop_back();
        for (Index f : at(m.cells, c).faces) {
            const mesh::Face& face = at(m.faces, f);
            if (face.boundary() || !has_edge(face.nodes))
                continue;
            const Index other = face.owner == c ? face.neighbour : face.owner;
            for (std::size_t j = 0; j < ring.size(); ++j)
                if (ring[j] == other && !seen[j]) {
                    seen[j] = 1;
                    ++reached;
                    stack.push_back(j);
                }
        }
    }
    return reached < ring.size();
}

std::vector<Index> sorted(std::vector<Index> v) {
    std::sort(v.begin(), v.end());
    return v;
}

// Fans a boundary face around a new node at its centroid; returns the new node.
Index fan_pocket(Editor& ed, Index f, Index cell, const Vec3& X, const Weights& w) {
    mesh::Mesh& m = ed.m;
    const Index q = ed.add_node(X, w, cell, NodeOrigin::Kind::Pocket);
    const std::vector<Index> loop = at(m.faces, f).nodes;
    at(m.faces, f).nodes = { q, loop[0], loop[1] };
    for (std::size_t i = 1; i < loop.size(); ++i) {
        mesh::Face tri = at(m.faces, f);
        tri.nodes = { q, loop[i], loop[(i + 1) % loop.size()] };
        tri.parent = f;
        ed.report->cut_faces.push_back(ed.add_face(std::move(tri)));
    }
    at(m.cells, cell).nodes.push_back(q);
    at(ed.node_cells, q).push_back(cell);
    ed.touch(cell);
    return q;
}
} // namespace

void fix_pinched_edges(Editor& ed) {
    // An edge that separated cells still share (a cut reaching the skin along it, or a later
    // plane split drawing a chord between two crack-front nodes of a Cut face) is non-manifold:
    // split it at its midpoint and separate the midpoint. Only edges of changed cells can be new.
    mesh::Mesh& m = ed.m;
    for (std::size_t k = 0; k < ed.changed_cells().size(); ++k) {
        const Index c = ed.changed_cells()[k];
        for (std::size_t j = 0; j < at(m.cells, c).faces.size(); ++j) {
            const Index f = at(m.cells, c).faces[j];
            if (!at(m.faces, f).boundary())
                continue; // a pinched edge has boundary faces on both sides
            for (std::size_t i = 0; i < at(m.faces, f).nodes.size(); ++i) {
                const auto& loop = at(m.faces, f).nodes;
                const Index a = loop[i], b = loop[(i + 1) % loop.size()];
                if (!ring_disconnected(ed, a, b))
                    continue;
                const Index mid = ed.split_edge(a, b, 0.5, c);
                split_node(ed, mid);
            }
        }
    }
}

void separate(Editor& ed, const std::vector<Index>& crack) {
    mesh::Mesh& m = ed.m;
    std::vector<std::pair<Index, Index>> pairs; // (face kept by owner, twin for the neighbour)
    std::vector<Index> nodes;
    for (Index f : crack) {
        mesh::Face& face = at(m.faces, f);
        const Index y = face.neighbour;
        mesh::Face twin;
        twin.nodes.assign(face.nodes.rbegin(), face.nodes.rend());
        twin.owner = y;
        twin.tag = mesh::FaceTag::Cut;
        twin.parent = f;
        face.neighbour = kNone;
        face.tag = mesh::FaceTag::Cut;
        nodes.insert(nodes.end(), face.nodes.begin(), face.nodes.end());
        auto& yf = at(m.cells, y).faces;
        yf.erase(std::remove(yf.begin(), yf.end(), f), yf.end());
        ed.touch(face.owner);
        const Index g = ed.add_face(std::move(twin));
        pairs.emplace_back(f, g);
        ed.report->cut_faces.push_back(f);
        ed.report->cut_faces.push_back(g);
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (Index n : nodes)
        split_node(ed, n);
    fix_pinched_edges(ed);

    // 000 sec. 5.2: if no node inside the cut shape separated, the cut cannot open; a pocket
    // node at the centroid of the largest covered face opens it.
    if (!ed.opt.pockets || pairs.empty())
        return;
    bool opened = false;
    for (const auto& [f, g] : pairs)
        opened = opened || sorted(at(m.faces, f).nodes) != sorted(at(m.faces, g).nodes);
    if (opened)
        return;
    double best = -1;
    std::pair<Index, Index> pick { kNone, kNone };
    for (const auto& pr : pairs) {
        const double a
            = geometry::polygon_area(geometry::gather(m.rest, at(m.faces, pr.first).nodes));
        if (a > best) {
            best = a;
            pick = pr;
        }
    }
    const auto& loop = at(m.faces, pick.first).nodes;
    const auto pts = geometry::gather(m.rest, loop);
    const auto cw = centroid_weights(pts);
    Vec3 X = Vec3::Zero();
    Weights w;
    {
        std::map<Index, double> sum;
        for (std::size_t i = 0; i < loop.size(); ++i) {
            X += cw[i] * pts[i];
            for (const auto& [node, wn] : ed.weights_of(loop[i]))
                sum[node] += cw[i] * wn;
        }
        w.assign(sum.begin(), sum.end());
    }
    fan_pocket(ed, pick.first, at(m.faces, pick.first).owner, X, w);
    fan_pocket(ed, pick.second, at(m.faces, pick.second).owner, X, w);
    ed.report->pockets += 1;
}

} // namespace polycut::cut::detail
