// Hexahedral slicing (hex_slice.hpp, 003 sec. 10). The surface, refined along the grid planes
// (hex_slice_grid.cpp, CGAL), gives every cut cube its skin triangles. A cube's faces on the
// grid planes are traced from two kinds of edges: the border of the cube's skin patch (reversed)
// and the parts of the square's sides that lie inside the surface (a side alternates inside /
// outside at the points where the surface crosses it). The skin triangles and the traced loops
// of a cube fall into connected pieces; each piece is a closed polyhedron. Small pieces are then
// merged into neighbours (003 sec. 10, sliver merging), and the faces two merged pieces share
// are dropped.
#include "polycut/meshing/hex_slice.hpp"

#include "hex_slice_grid.hpp"
#include "hex_slice_merge.hpp"
#include "polycut/common/error.hpp"
#include "surface_prepare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace polycut::meshing {

namespace {

using detail::DegenerateGrid;
using detail::Loop;
using detail::Piece;
using detail::SlicedSurface;
using detail::SliceGrid;
using detail::sorted;
using detail::UnionFind;
using Cube = std::array<int, 3>;

/// Grid planes around the surface's bounding box with at least h / 2 of margin, moved by
/// `shift` cubes (a small irrational-looking offset per attempt, so that round surface
/// coordinates do not land on planes).
SliceGrid make_grid(const SurfaceMesh& s, double h, int attempt) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& p : s.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Vec3 offset = (1 + attempt) * Vec3(0.0123456789, 0.0234567891, 0.0345678912);
    SliceGrid g;
    for (int a = 0; a < 3; ++a) {
        const int n = int(std::ceil((hi[a] - lo[a]) / h)) + 1;
        const double origin = 0.5 * (lo[a] + hi[a]) - 0.5 * n * h + offset[a] * h;
        for (int i = 0; i <= n; ++i)
            g.planes[std::size_t(a)].push_back(origin + i * h);
    }
    return g;
}

struct Pair {
    Index a, b;
    bool operator==(const Pair&) const = default;
};
struct PairHash {
    std::size_t operator()(const Pair& p) const {
        return std::hash<long long>()((long long)(p.a) * 1000003LL ^ (long long)(p.b));
    }
};

/// The builder of one attempt; throws DegenerateGrid when the grid must move.
class Slicer {
public:
    Slicer(const SurfaceMesh& surface, const SliceGrid& grid)
        : m_surface(surface)
        , m_grid(grid)
        , m_sliced(detail::slice_surface(surface, grid)) {
        for (int a = 0; a < 3; ++a)
            m_n[std::size_t(a)] = grid.cubes(a);
        m_point_node.assign(m_sliced.points.size(), kNone);
        m_corner_node.assign(std::size_t(corner_id({ m_n[0], m_n[1], m_n[2] }) + 1), kNone);
        std::vector<Vec3> corners(m_corner_node.size());
        for (int k = 0; k <= m_n[2]; ++k)
            for (int j = 0; j <= m_n[1]; ++j)
                for (int i = 0; i <= m_n[0]; ++i)
                    corners[std::size_t(corner_id({ i, j, k }))] = corner({ i, j, k });
        m_corner_side = detail::sides(surface, corners);
        collect_crossings();
    }

    std::vector<Piece> pieces(Index& holed) {
        std::vector<std::vector<Index>> by_cube(std::size_t(cube_id(m_n)));
        for (std::size_t t = 0; t < m_sliced.triangles.size(); ++t)
            by_cube[std::size_t(cube_id(m_sliced.cube[t]))].push_back(Index(t));
        std::vector<Piece> out;
        for (int k = 0; k < m_n[2]; ++k)
            for (int j = 0; j < m_n[1]; ++j)
                for (int i = 0; i < m_n[0]; ++i) {
                    const Cube c { i, j, k };
                    const auto& tris = by_cube[std::size_t(cube_id(c))];
                    if (!tris.empty())
                        cut_cube(c, tris, out);
                    else if (m_corner_side[std::size_t(corner_id(c))] > 0)
                        out.push_back(hex_piece(c));
                }
        holed = Index(m_holed.size());
        return out;
    }

    const std::vector<Vec3>& nodes() const { return m_nodes; }
    const std::unordered_set<long>& holed_squares() const { return m_holed; }
    Index sliced_triangles() const { return Index(m_sliced.triangles.size()); }
    std::array<Index, 3> cubes() const { return { m_n[0], m_n[1], m_n[2] }; }

private:
    long cube_id(const Cube& c) const { return c[0] + long(m_n[0]) * (c[1] + long(m_n[1]) * c[2]); }
    long corner_id(const Cube& c) const {
        return c[0] + long(m_n[0] + 1) * (c[1] + long(m_n[1] + 1) * c[2]);
    }
    Vec3 corner(const Cube& c) const {
        return { m_grid.planes[0][std::size_t(c[0])], m_grid.planes[1][std::size_t(c[1])],
            m_grid.planes[2][std::size_t(c[2])] };
    }
    /// Square on plane `index` of `axis`, spanning slabs (s1, s2) of the next two axes.
    long square_id(int axis, int index, int s1, int s2) const {
        return axis + 3L * (index + 1001L * (s1 + 1001L * long(s2)));
    }
    /// Grid edge along `axis` starting at corner c.
    long edge_id(int axis, const Cube& c) const { return axis + 3L * corner_id(c); }

    Index corner_node(const Cube& c) {
        Index& n = m_corner_node[std::size_t(corner_id(c))];
        if (n == kNone) {
            n = Index(m_nodes.size());
            m_nodes.push_back(corner(c));
        }
        return n;
    }
    Index point_node(Index p) {
        Index& n = m_point_node[std::size_t(p)];
        if (n == kNone) {
            n = Index(m_nodes.size());
            m_nodes.push_back(m_sliced.points[std::size_t(p)]);
        }
        return n;
    }

    /// Surface points on grid lines (on two planes), sorted along the line.
    void collect_crossings() {
        for (std::size_t p = 0; p < m_sliced.points.size(); ++p) {
            const auto& pl = m_sliced.plane[p];
            const int on = (pl[0] >= 0) + (pl[1] >= 0) + (pl[2] >= 0);
            if (on != 2)
                continue;
            const int free = pl[0] < 0 ? 0 : pl[1] < 0 ? 1 : 2;
            Cube start = pl;
            start[std::size_t(free)] = m_sliced.slab[p][std::size_t(free)];
            m_crossings[edge_id(free, start)].push_back(Index(p));
        }
        for (auto& [key, list] : m_crossings) {
            const int axis = int(key % 3);
            std::sort(list.begin(), list.end(), [&](Index a, Index b) {
                return m_sliced.points[std::size_t(a)][axis]
                    < m_sliced.points[std::size_t(b)][axis];
            });
        }
    }

    Piece hex_piece(const Cube& c) {
        std::array<Index, 8> n {};
        static constexpr std::array<std::array<int, 3>, 8> kOffsets { { { 0, 0, 0 }, { 1, 0, 0 },
            { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } } };
        for (std::size_t v = 0; v < 8; ++v)
            n[v] = corner_node(
                { c[0] + kOffsets[v][0], c[1] + kOffsets[v][1], c[2] + kOffsets[v][2] });
        Piece piece;
        piece.hex = true;
        piece.cube = cube_id(c);
        for (const auto& f : mesh::kHexFaces) {
            piece.loops.push_back({ n[std::size_t(f[0])], n[std::size_t(f[1])],
                n[std::size_t(f[2])], n[std::size_t(f[3])] });
            // The square of this face: the axis its four corners share.
            int axis = 0;
            for (int a = 0; a < 3; ++a)
                if (kOffsets[std::size_t(f[0])][std::size_t(a)]
                        == kOffsets[std::size_t(f[1])][std::size_t(a)]
                    && kOffsets[std::size_t(f[0])][std::size_t(a)]
                        == kOffsets[std::size_t(f[2])][std::size_t(a)])
                    axis = a;
            const int index = c[std::size_t(axis)] + kOffsets[std::size_t(f[0])][std::size_t(axis)];
            piece.square.push_back(square_id(
                axis, index, c[std::size_t((axis + 1) % 3)], c[std::size_t((axis + 2) % 3)]));
        }
        const double h = m_grid.planes[0][1] - m_grid.planes[0][0];
        piece.volume = h * h * h;
        return piece;
    }

    /// The inside parts of the square's side from corner p to corner q (which differ along one
    /// axis), as directed edges appended to `next`.
    void side_edges(const Cube& p, const Cube& q, std::unordered_map<Index, Index>& next) {
        int axis = 0;
        while (p[std::size_t(axis)] == q[std::size_t(axis)])
            ++axis;
        const bool up = q[std::size_t(axis)] > p[std::size_t(axis)];
        std::vector<Index> seq { corner_node(p) };
        if (auto it = m_crossings.find(edge_id(axis, up ? p : q)); it != m_crossings.end()) {
            std::vector<Index> pts = it->second;
            if (!up)
                std::reverse(pts.begin(), pts.end());
            for (Index pt : pts)
                seq.push_back(point_node(pt));
        }
        seq.push_back(corner_node(q));
        bool inside = m_corner_side[std::size_t(corner_id(p))] > 0;
        for (std::size_t s = 0; s + 1 < seq.size(); ++s) {
            if (inside && !next.emplace(seq[s], seq[s + 1]).second)
                throw DegenerateGrid("two face edges leave one node");
            inside = !inside;
        }
        if (!inside != (m_corner_side[std::size_t(corner_id(q))] > 0))
            throw DegenerateGrid("the surface touches a grid edge without crossing it");
    }

    /// The pieces of a cube the surface crosses.
    void cut_cube(const Cube& c, const std::vector<Index>& tris, std::vector<Piece>& out) {
        std::unordered_set<Pair, PairHash> directed;
        for (Index t : tris) {
            const auto& tri = m_sliced.triangles[std::size_t(t)];
            for (int e = 0; e < 3; ++e)
                directed.insert({ tri[std::size_t(e)], tri[std::size_t((e + 1) % 3)] });
        }
        // Per cube face (axis a, side s -> 2a + s): the loop edges, node -> next node.
        std::array<std::unordered_map<Index, Index>, 6> next;
        for (const Pair& e : directed) {
            if (directed.count({ e.b, e.a }))
                continue;
            int face = -1;
            for (int a = 0; a < 3; ++a) {
                const int pa = m_sliced.plane[std::size_t(e.a)][std::size_t(a)];
                if (pa >= 0 && pa == m_sliced.plane[std::size_t(e.b)][std::size_t(a)]) {
                    if (face >= 0)
                        throw DegenerateGrid("a surface edge lies on a grid line");
                    face = 2 * a + (pa == c[std::size_t(a)] ? 0 : 1);
                }
            }
            if (face < 0)
                throw DegenerateGrid("a skin border edge off the cube's faces");
            if (!next[std::size_t(face)].emplace(point_node(e.b), point_node(e.a)).second)
                throw DegenerateGrid("the surface touches a cube face at a point");
        }
        std::vector<Loop> loops;
        std::vector<long> squares;
        for (int a = 0; a < 3; ++a)
            for (int s = 0; s < 2; ++s) {
                auto& nx = next[std::size_t(2 * a + s)];
                const int a1 = (a + 1) % 3, a2 = (a + 2) % 3;
                // Corners counter-clockwise about the outward normal (+a for s = 1).
                std::array<Cube, 4> q;
                const std::array<std::array<int, 2>, 4> ccw { { { 0, 0 }, { 1, 0 }, { 1, 1 },
                    { 0, 1 } } };
                for (std::size_t v = 0; v < 4; ++v) {
                    const auto& d = ccw[s == 1 ? v : (4 - v) % 4];
                    q[v] = c;
                    q[v][std::size_t(a)] += s;
                    q[v][std::size_t(a1)] += d[0];
                    q[v][std::size_t(a2)] += d[1];
                }
                for (std::size_t v = 0; v < 4; ++v)
                    side_edges(q[v], q[(v + 1) % 4], nx);
                const long square
                    = square_id(a, c[std::size_t(a)] + s, c[std::size_t(a1)], c[std::size_t(a2)]);
                Vec3 normal = Vec3::Zero();
                normal[a] = s == 1 ? 1 : -1;
                trace(nx, normal, square, loops, squares);
            }
        for (Index t : tris) {
            const auto& tri = m_sliced.triangles[std::size_t(t)];
            loops.push_back({ point_node(tri[0]), point_node(tri[1]), point_node(tri[2]) });
            squares.push_back(-1);
        }
        split_pieces(c, loops, squares, out);
    }

    /// Closed loops of the face edges `next`; a loop turning clockwise about `normal` is a hole.
    void trace(std::unordered_map<Index, Index>& next, const Vec3& normal, long square,
        std::vector<Loop>& loops, std::vector<long>& squares) {
        while (!next.empty()) {
            Loop loop { next.begin()->first };
            for (;;) {
                auto it = next.find(loop.back());
                if (it == next.end())
                    throw DegenerateGrid("an open face loop");
                const Index to = it->second;
                next.erase(it);
                if (to == loop.front())
                    break;
                loop.push_back(to);
            }
            Vec3 area = Vec3::Zero();
            for (std::size_t i = 0; i < loop.size(); ++i)
                area += m_nodes[std::size_t(loop[i])].cross(
                    m_nodes[std::size_t(loop[(i + 1) % loop.size()])]);
            if (area.dot(normal) < 0)
                m_holed.insert(square);
            loops.push_back(std::move(loop));
            squares.push_back(square);
        }
    }

    /// Connected components (through shared edges) of a cube's loops, each a piece.
    void split_pieces(const Cube& c, const std::vector<Loop>& loops,
        const std::vector<long>& squares, std::vector<Piece>& out) {
        UnionFind uf(loops.size());
        std::unordered_map<Pair, Index, PairHash> first;
        for (std::size_t l = 0; l < loops.size(); ++l)
            for (std::size_t i = 0; i < loops[l].size(); ++i) {
                Index a = loops[l][i], b = loops[l][(i + 1) % loops[l].size()];
                if (a > b)
                    std::swap(a, b);
                auto [it, inserted] = first.emplace(Pair { a, b }, Index(l));
                if (!inserted)
                    uf.unite(it->second, Index(l));
            }
        std::map<Index, std::size_t> piece_of_root;
        const std::size_t begin = out.size();
        for (std::size_t l = 0; l < loops.size(); ++l) {
            const Index root = uf.find(Index(l));
            auto [it, inserted] = piece_of_root.emplace(root, out.size());
            if (inserted) {
                out.emplace_back();
                out.back().cube = cube_id(c);
            }
            Piece& p = out[it->second];
            p.loops.push_back(loops[l]);
            p.square.push_back(squares[l]);
        }
        const Vec3 centre = corner(c);
        for (std::size_t p = begin; p < out.size(); ++p)
            out[p].volume = volume(out[p].loops, centre);
    }

public:
    /// Volume enclosed by outward loops (fans about each loop's first node, divergence theorem
    /// about `ref` for accuracy) [m^3].
    double volume(const std::vector<Loop>& loops, const Vec3& ref) const {
        double v = 0;
        for (const Loop& l : loops) {
            const Vec3 a = m_nodes[std::size_t(l[0])] - ref;
            for (std::size_t i = 1; i + 1 < l.size(); ++i)
                v += a.dot(
                    (m_nodes[std::size_t(l[i])] - ref).cross(m_nodes[std::size_t(l[i + 1])] - ref));
        }
        return v / 6;
    }
    /// Area of a planar loop [m^2].
    double area(const Loop& l) const {
        Vec3 a = Vec3::Zero();
        for (std::size_t i = 0; i < l.size(); ++i)
            a += m_nodes[std::size_t(l[i])].cross(m_nodes[std::size_t(l[(i + 1) % l.size()])]);
        return 0.5 * a.norm();
    }

private:
    const SurfaceMesh& m_surface;
    const SliceGrid& m_grid;
    SlicedSurface m_sliced;
    std::array<int, 3> m_n {};
    std::vector<Index> m_point_node, m_corner_node;
    std::vector<int> m_corner_side;
    std::vector<Vec3> m_nodes;
    std::unordered_map<long, std::vector<Index>> m_crossings;
    std::unordered_set<long> m_holed;
};

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

mesh::Mesh build(
    const SurfaceMesh& s, const SliceGrid& grid, double threshold, HexSliceReport& report) {
    Slicer slicer(s, grid);
    Index holed = 0;
    std::vector<Piece> pieces = slicer.pieces(holed);
    report.grid = slicer.cubes();
    report.sliced_triangles = slicer.sliced_triangles();
    report.holed_faces = holed;
    report.pieces = 0;
    for (const Piece& p : pieces)
        report.pieces += !p.hex && p.volume > 0;
    const std::vector<Index> group = detail::merge_pieces(
        pieces, [&](const Loop& l) { return slicer.area(l); }, slicer.holed_squares(), threshold,
        report);

    // One cell per group; faces two of its pieces share are dropped.
    std::map<Index, std::vector<std::size_t>> members;
    for (std::size_t p = 0; p < pieces.size(); ++p)
        members[group[p]].push_back(p);
    std::vector<std::vector<Loop>> cells;
    for (const auto& [root, list] : members) {
        if (list.size() == 1) {
            cells.push_back(pieces[list[0]].loops);
            if (pieces[list[0]].hex)
                ++report.hexes;
            continue;
        }
        std::map<Loop, int> count;
        for (std::size_t p : list)
            for (const Loop& l : pieces[p].loops)
                ++count[sorted(l)];
        std::vector<Loop> loops;
        for (std::size_t p : list)
            for (const Loop& l : pieces[p].loops)
                if (count[sorted(l)] == 1)
                    loops.push_back(l);
        cells.push_back(std::move(loops));
    }
    report.cut_cells = Index(cells.size()) - report.hexes;
    // Compact the nodes (corners only used by dropped faces go).
    const std::vector<Vec3>& all = slicer.nodes();
    std::vector<Index> id(all.size(), kNone);
    std::vector<Vec3> rest;
    for (auto& cell : cells)
        for (Loop& l : cell)
            for (Index& v : l) {
                if (id[std::size_t(v)] == kNone) {
                    id[std::size_t(v)] = Index(rest.size());
                    rest.push_back(all[std::size_t(v)]);
                }
                v = id[std::size_t(v)];
            }
    return mesh::Mesh::from_polyhedra(std::move(rest), cells);
}

} // namespace

std::string HexSliceReport::summary() const {
    char text[400];
    std::snprintf(text, sizeof text,
        "%ldx%ldx%ld cubes, %ld hexes + %ld cut cells (%ld pieces, %ld merged, %ld holed faces, "
        "%ld small kept), %ld -> %ld surface triangles, volume %.6e m^3 (surface %.6e, rel. "
        "diff %.1e), smallest cell %.3e m^3, %ld grid shifts, %.0f ms",
        long(grid[0]), long(grid[1]), long(grid[2]), long(hexes), long(cut_cells), long(pieces),
        long(merged), long(holed_faces), long(small_kept), long(surface_triangles),
        long(sliced_triangles), mesh_volume, surface_volume,
        surface_volume != 0 ? mesh_volume / surface_volume - 1 : 0.0, min_cell_volume,
        long(grid_shifts), time_ms);
    return text;
}

mesh::Mesh hex_slice(
    const SurfaceMesh& surface, const HexSliceOptions& options, HexSliceReport* report) {
    const auto start = std::chrono::steady_clock::now();
    if (!(std::isfinite(options.cell_size) && options.cell_size > 0))
        throw InputError("options.cell_size", "must be finite and > 0 [m]");
    if (!(options.merge_fraction >= 0 && options.merge_fraction < 1))
        throw InputError("options.merge_fraction", "must be in [0, 1)");
    SurfaceMesh s = surface;
    if (std::string problem = detail::prepare_closed_surface(s); !problem.empty())
        throw InputError("surface", problem);
    HexSliceReport r;
    r.surface_triangles = Index(s.triangles.size());
    r.surface_volume = enclosed_volume(s);
    const double h = options.cell_size;
    {
        Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
        for (const Vec3& p : s.positions) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        const Vec3 cubes = (hi - lo) / h;
        if (cubes.prod() > 2e6)
            throw InputError("options.cell_size",
                "gives " + std::to_string(long(cubes.prod())) + " grid cubes (more than 2e6)");
    }
    constexpr int kAttempts = 6;
    mesh::Mesh m;
    for (int attempt = 0;; ++attempt) {
        HexSliceReport trial = r;
        try {
            m = build(s, make_grid(s, h, attempt), options.merge_fraction * h * h * h, trial);
            r = trial;
            r.grid_shifts = attempt;
            break;
        } catch (const DegenerateGrid& e) {
            if (attempt + 1 == kAttempts)
                throw MeshError(-1, -1,
                    std::string("hex slicing: the grid stays degenerate after moving it ")
                        + std::to_string(kAttempts) + " times (" + e.what() + ")");
        }
    }
    if (m.num_cells() == 0)
        throw MeshError(-1, -1, "hex slicing produced no cell");
    r.min_cell_volume = 1e300;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const double v = m.cell_volume(c);
        r.mesh_volume += v;
        r.min_cell_volume = std::min(r.min_cell_volume, v);
    }
    r.time_ms = ms_since(start);
    if (report)
        *report = r;
    return m;
}

} // namespace polycut::meshing
