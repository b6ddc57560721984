// The octree's kept leaves as polyhedral cells with matching faces (001 Fig. 4).
//
// Each side of a leaf is tiled by the sides of the leaves across it: one quad when the leaf
// across is as large or larger (or when nothing kept is across: one boundary quad), the four
// quads of the finer leaves otherwise. Every corner of such a quad is a node; a quad's loop then
// takes, along each edge, the nodes other cells put there (the midpoint a finer neighbour along
// that edge makes). Both cells of an interior quad build the same rectangle from the same node
// set, so Mesh::from_polyhedra matches them as one face. Kept leaves that touch the rest only
// along an edge or at a corner would make a non-manifold boundary; the dropped leaves around
// such a node are kept too, and the mesh built again.
#include "polycut/common/error.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/octree.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

namespace polycut::meshing {
namespace {
using Point = std::array<int, 3>;

std::uint64_t point_key(const Point& p) {
    return (std::uint64_t(p[0]) << 42) | (std::uint64_t(p[1]) << 21) | std::uint64_t(p[2]);
}

/// Key of the axis-parallel line through p along `axis`.
std::uint64_t line_key(int axis, const Point& p) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    return (std::uint64_t(axis) << 60) | (std::uint64_t(p[std::size_t(b)]) << 30)
        | std::uint64_t(p[std::size_t(c)]);
}

/// Nodes of the boundary that is not a 2-manifold: on an edge used by other than two boundary
/// faces, or where the boundary faces around a node form more than one fan.
std::vector<Index> non_manifold_nodes(const mesh::Mesh& m) {
    std::map<std::pair<Index, Index>, int> edge_use;
    std::vector<std::vector<Index>> node_faces(std::size_t(m.num_nodes()));
    for (Index f = 0; f < m.num_faces(); ++f) {
        const mesh::Face& face = m.faces[std::size_t(f)];
        if (!face.boundary())
            continue;
        const std::size_t k = face.nodes.size();
        for (std::size_t i = 0; i < k; ++i) {
            const Index a = face.nodes[i], b = face.nodes[(i + 1) % k];
            ++edge_use[{ std::min(a, b), std::max(a, b) }];
            node_faces[std::size_t(a)].push_back(f);
        }
    }
    std::vector<std::uint8_t> bad(std::size_t(m.num_nodes()), 0);
    for (const auto& [edge, uses] : edge_use)
        if (uses != 2)
            bad[std::size_t(edge.first)] = bad[std::size_t(edge.second)] = 1;
    // fans: the faces around node v joined through the edges at v they share
    for (Index v = 0; v < m.num_nodes(); ++v) {
        const auto& faces = node_faces[std::size_t(v)];
        if (faces.size() < 2 || bad[std::size_t(v)])
            continue;
        std::vector<std::size_t> parent(faces.size());
        std::iota(parent.begin(), parent.end(), 0);
        auto find = [&](std::size_t i) {
            while (parent[i] != i)
                i = parent[i] = parent[parent[i]];
            return i;
        };
        std::map<Index, std::size_t> by_other; // other end of an edge at v -> face slot
        for (std::size_t s = 0; s < faces.size(); ++s) {
            const auto& loop = m.faces[std::size_t(faces[s])].nodes;
            const std::size_t k = loop.size();
            const std::size_t i
                = std::size_t(std::find(loop.begin(), loop.end(), v) - loop.begin());
            for (Index other : { loop[(i + 1) % k], loop[(i + k - 1) % k] }) {
                auto [it, inserted] = by_other.try_emplace(other, s);
                if (!inserted)
                    parent[find(s)] = find(it->second);
            }
        }
        std::size_t roots = 0;
        for (std::size_t s = 0; s < faces.size(); ++s)
            roots += find(s) == s;
        if (roots > 1)
            bad[std::size_t(v)] = 1;
    }
    std::vector<Index> out;
    for (Index v = 0; v < m.num_nodes(); ++v)
        if (bad[std::size_t(v)])
            out.push_back(v);
    return out;
}
} // namespace

struct OctreeMeshBuilder {
    Octree& tree;
    std::vector<Point> node_points; ///< unit coordinates of each mesh node

    struct Quad {
        int u = 0, v = 0, len = 0;
        bool boundary = false;
    };

    /// The quads tiling the square (u, v, len) of side `axis` at coordinate `across` (just
    /// outside the leaf), down to the leaves there.
    void tile(int axis, int across, Quad q, std::vector<Quad>& out) const {
        const int b = (axis + 1) % 3, c = (axis + 2) % 3;
        Point p {};
        p[std::size_t(axis)] = across;
        p[std::size_t(b)] = q.u;
        p[std::size_t(c)] = q.v;
        const int leaf = tree.leaf_at(p);
        if (leaf < 0 || tree.m_nodes[std::size_t(leaf)].size >= q.len || q.len == 1) {
            q.boundary = leaf < 0 || !tree.m_nodes[std::size_t(leaf)].kept;
            out.push_back(q);
            return;
        }
        const int h = q.len / 2;
        for (int i = 0; i < 4; ++i)
            tile(axis, across, Quad { q.u + (i & 1) * h, q.v + (i >> 1) * h, h }, out);
    }

    /// Outward corner loops of the quads tiling a leaf's six sides.
    std::vector<std::array<Point, 4>> side_quads(int leaf) const {
        const auto& n = tree.m_nodes[std::size_t(leaf)];
        std::vector<std::array<Point, 4>> loops;
        std::vector<Quad> quads;
        for (int axis = 0; axis < 3; ++axis)
            for (int sign : { -1, 1 }) {
                const int b = (axis + 1) % 3, c = (axis + 2) % 3;
                const int plane = n.lo[std::size_t(axis)] + (sign > 0 ? n.size : 0);
                quads.clear();
                tile(axis, sign > 0 ? plane : plane - 1,
                    Quad { n.lo[std::size_t(b)], n.lo[std::size_t(c)], n.size }, quads);
                if (std::all_of(
                        quads.begin(), quads.end(), [](const Quad& q) { return q.boundary; }))
                    quads.assign(
                        1, Quad { n.lo[std::size_t(b)], n.lo[std::size_t(c)], n.size, true });
                for (const Quad& q : quads) {
                    std::array<Point, 4> loop {};
                    const int du[4] = { 0, q.len, q.len, 0 }, dv[4] = { 0, 0, q.len, q.len };
                    for (int i = 0; i < 4; ++i) {
                        Point& p = loop[std::size_t(sign > 0 ? i : 3 - i)];
                        p[std::size_t(axis)] = plane;
                        p[std::size_t(b)] = q.u + du[i];
                        p[std::size_t(c)] = q.v + dv[i];
                    }
                    loops.push_back(loop);
                }
            }
        return loops;
    }

    mesh::Mesh build(const std::vector<int>& leaves) {
        std::vector<std::vector<std::array<Point, 4>>> quads(leaves.size());
        std::unordered_map<std::uint64_t, Index> node_of;
        node_points.clear();
        for (std::size_t c = 0; c < leaves.size(); ++c) {
            quads[c] = side_quads(leaves[c]);
            for (const auto& loop : quads[c])
                for (const Point& p : loop)
                    if (node_of.try_emplace(point_key(p), Index(node_points.size())).second)
                        node_points.push_back(p);
        }
        std::unordered_map<std::uint64_t, std::vector<int>> lines;
        for (const Point& p : node_points)
            for (int axis = 0; axis < 3; ++axis)
                lines[line_key(axis, p)].push_back(p[std::size_t(axis)]);
        for (auto& [key, coords] : lines)
            std::sort(coords.begin(), coords.end());

        std::vector<std::vector<std::vector<Index>>> cells(leaves.size());
        for (std::size_t c = 0; c < leaves.size(); ++c)
            for (const auto& corners : quads[c]) {
                std::vector<Index> loop;
                for (int i = 0; i < 4; ++i) {
                    const Point& from = corners[std::size_t(i)];
                    const Point& to = corners[std::size_t((i + 1) % 4)];
                    loop.push_back(node_of.at(point_key(from)));
                    int axis = 0;
                    while (from[std::size_t(axis)] == to[std::size_t(axis)])
                        ++axis;
                    const auto& coords = lines.at(line_key(axis, from));
                    const int a = from[std::size_t(axis)], b = to[std::size_t(axis)];
                    auto lo = std::upper_bound(coords.begin(), coords.end(), std::min(a, b));
                    auto hi = std::lower_bound(coords.begin(), coords.end(), std::max(a, b));
                    std::vector<int> between(lo, hi);
                    if (a > b)
                        std::reverse(between.begin(), between.end());
                    for (int x : between) {
                        Point p = from;
                        p[std::size_t(axis)] = x;
                        loop.push_back(node_of.at(point_key(p)));
                    }
                }
                cells[c].push_back(std::move(loop));
            }
        std::vector<Vec3> rest;
        rest.reserve(node_points.size());
        for (const Point& p : node_points)
            rest.push_back(tree.position(p));
        return mesh::Mesh::from_polyhedra(std::move(rest), cells);
    }

    /// Keeps the dropped leaves around these nodes; returns how many it kept.
    int fill_around(const std::vector<Index>& nodes) {
        int added = 0;
        for (Index v : nodes) {
            const Point& p = node_points[std::size_t(v)];
            for (int d = 0; d < 8; ++d) {
                Point q { p[0] - (d & 1), p[1] - ((d >> 1) & 1), p[2] - ((d >> 2) & 1) };
                const int leaf = tree.leaf_at(q);
                if (leaf >= 0 && !tree.m_nodes[std::size_t(leaf)].kept) {
                    tree.m_nodes[std::size_t(leaf)].kept = true;
                    ++added;
                }
            }
        }
        return added;
    }
};

mesh::Mesh Octree::build_mesh() {
    OctreeMeshBuilder builder { *this, {} };
    for (int round = 0;; ++round) {
        m_cell_leaves.clear();
        for (int n = 0; n < int(m_nodes.size()); ++n)
            if (m_nodes[std::size_t(n)].first_child < 0 && m_nodes[std::size_t(n)].kept)
                m_cell_leaves.push_back(n);
        if (m_cell_leaves.empty())
            throw InputError("cell_size", "no cell of the octree overlaps the object");
        mesh::Mesh m = builder.build(m_cell_leaves);
        const std::vector<Index> bad = non_manifold_nodes(m);
        if (bad.empty()) {
            mesh::validate(m);
            return m;
        }
        if (round > 64 || builder.fill_around(bad) == 0)
            throw MeshError(-1, -1,
                "octree: the boundary is not a 2-manifold at " + std::to_string(bad.size())
                    + " nodes after filling");
    }
}

} // namespace polycut::meshing
