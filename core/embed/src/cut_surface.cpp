// The rest-space cut surface (cut_surface.hpp). Outline:
// 1. the two sides: faces sharing an edge are on the same side when their normals agree (on
//    opposite sides across the crack front, where the lips fold), and a face whose rest polygon
//    is another's is on the other side (parity union-find);
// 2. the corners of all faces welded within a rounding tolerance (grid hash);
// 3. side 0's faces: every welded corner on one of their edges inserted into that edge, then
//    each loop ear-clipped in its plane (collinear corners are never ears, so they stay on the
//    edges their neighbours share).
#include "cut_surface.hpp"

#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <unordered_map>

namespace polycut::embed::detail {

namespace {

/// Points hashed on a uniform grid of cell size h.
class PointGrid {
public:
    explicit PointGrid(double h)
        : m_h(h) { }
    std::array<long long, 3> cell(const Vec3& p) const {
        return { (long long)std::floor(p.x() / m_h), (long long)std::floor(p.y() / m_h),
            (long long)std::floor(p.z() / m_h) };
    }
    void insert(const Vec3& p, std::uint32_t id) { m_cells[cell(p)].push_back(id); }
    /// Calls f(id) for the ids in the cells that meet the box [lo, hi].
    template <class F> void visit(const Vec3& lo, const Vec3& hi, F&& f) const {
        const auto a = cell(lo), b = cell(hi);
        for (long long i = a[0]; i <= b[0]; ++i)
            for (long long j = a[1]; j <= b[1]; ++j)
                for (long long k = a[2]; k <= b[2]; ++k)
                    if (const auto it = m_cells.find({ i, j, k }); it != m_cells.end())
                        for (const std::uint32_t id : it->second)
                            f(id);
    }

private:
    struct Hash {
        std::size_t operator()(const std::array<long long, 3>& c) const {
            return std::size_t(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
        }
    };
    double m_h;
    std::unordered_map<std::array<long long, 3>, std::vector<std::uint32_t>, Hash> m_cells;
};

/// Ear clipping of a planar loop (indices into `points`) with normal n; collinear corners are
/// not ears, nor corners whose ear has another corner inside or on it. A loop with no ear left
/// (rounding) is finished as a fan from its sharpest corner.
void ear_clip(const std::vector<Vec3>& points, std::vector<std::uint32_t> loop, const Vec3& n,
    std::vector<std::array<std::uint32_t, 3>>& out) {
    const Vec3 u = n.unitOrthogonal(), v = n.normalized().cross(u);
    auto flat = [&](std::uint32_t i) {
        const Vec3& p = points[i];
        return Eigen::Vector2d(p.dot(u), p.dot(v));
    };
    auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
        return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    };
    double scale = 0;
    for (std::size_t k = 0; k < loop.size(); ++k)
        scale = std::max(scale, (flat(loop[k]) - flat(loop[(k + 1) % loop.size()])).norm());
    const double eps = 1e-12 * scale * scale;
    while (loop.size() > 3) {
        const std::size_t m = loop.size();
        std::size_t ear = m;
        double sharpest = -std::numeric_limits<double>::infinity();
        std::size_t sharpest_at = 0;
        for (std::size_t k = 0; k < m && ear == m; ++k) {
            const auto a = flat(loop[(k + m - 1) % m]), b = flat(loop[k]),
                       c = flat(loop[(k + 1) % m]);
            const double turn = cross(a, b, c);
            if (turn > sharpest) {
                sharpest = turn;
                sharpest_at = k;
            }
            if (!(turn > eps))
                continue;
            bool empty = true;
            for (std::size_t j = 0; j < m && empty; ++j) {
                if (j == k || j == (k + 1) % m || j == (k + m - 1) % m)
                    continue;
                const auto p = flat(loop[j]);
                // A corner inside the ear or on its closing edge blocks it (on that edge, the
                // last triangle would be flat).
                empty
                    = !(cross(a, b, p) >= -eps && cross(b, c, p) >= -eps && cross(c, a, p) >= -eps);
            }
            if (empty)
                ear = k;
        }
        if (ear == m)
            ear = sharpest_at;
        out.push_back({ loop[(ear + m - 1) % m], loop[ear], loop[(ear + 1) % m] });
        loop.erase(loop.begin() + std::ptrdiff_t(ear));
    }
    if (loop.size() == 3)
        out.push_back({ loop[0], loop[1], loop[2] });
}

void update_boxes(CutSurface& s) {
    s.triangle_box.clear();
    s.all = Box {};
    for (const auto& tri : s.cut.triangles) {
        Box box;
        for (const std::uint32_t i : tri)
            box.add(s.cut.points[i]);
        s.all.add(box.lo);
        s.all.add(box.hi);
        s.triangle_box.push_back(box);
    }
}

/// The loops' triangles: every cut point within the tolerance of a loop's edge is inserted
/// into it (T-junctions), then each loop is ear-clipped in its own plane.
void triangulate(CutSurface& s) {
    const double tol = s.tolerance;
    s.cut.triangles.clear();
    s.triangle_face.clear();
    PointGrid coarse(s.edge_length);
    for (std::uint32_t id = 0; id < s.cut.points.size(); ++id)
        coarse.insert(s.cut.points[id], id);
    for (const auto& [face, corners] : s.loops) {
        std::vector<std::uint32_t> loop;
        for (std::size_t k = 0; k < corners.size(); ++k) {
            const std::uint32_t a = corners[k], b = corners[(k + 1) % corners.size()];
            loop.push_back(a);
            const Vec3 &pa = s.cut.points[a], &pb = s.cut.points[b];
            const Vec3 d = pb - pa;
            const double len2 = d.squaredNorm();
            if (!(len2 > 0))
                continue;
            std::vector<std::pair<double, std::uint32_t>> on_edge;
            coarse.visit(pa.cwiseMin(pb) - Vec3::Constant(tol),
                pa.cwiseMax(pb) + Vec3::Constant(tol), [&](std::uint32_t id) {
                    if (id == a || id == b)
                        return;
                    const Vec3& p = s.cut.points[id];
                    const double t = (p - pa).dot(d) / len2;
                    if (t <= 0 || t >= 1 || (pa + t * d - p).norm() > tol)
                        return;
                    on_edge.emplace_back(t, id);
                });
            std::sort(on_edge.begin(), on_edge.end());
            for (const auto& [t, id] : on_edge)
                loop.push_back(id);
        }
        std::vector<Vec3> at;
        for (const std::uint32_t id : loop)
            at.push_back(s.cut.points[id]);
        ear_clip(s.cut.points, loop, geometry::polygon_normal(at), s.cut.triangles);
        s.triangle_face.resize(s.cut.triangles.size(), face);
    }
    update_boxes(s);
}

/// Where a cut face ends on the mesh's skin, the cut surface is carried on outward in the
/// face's plane by a face's size: the detailed surface is not the mesh's boundary (a coarse
/// mesh's facets chord inside it; an octree keeps the leaves whose centre is inside), so a cut
/// that reached the mesh's boundary has parted the material up to the detailed surface, which
/// must be split there too. Only the part inside the detailed surface becomes lips. Each border
/// corner moves along the mean of its border edges' outward directions, so the extension's
/// quads share their corners.
void extend_past_the_mesh(
    CutSurface& s, const mesh::Mesh& mesh, const std::map<Index, std::uint32_t>& welded) {
    std::set<std::pair<Index, Index>> skin_edges;
    for (const mesh::Face& face : mesh.faces)
        if (face.boundary() && face.tag == mesh::FaceTag::Skin)
            for (std::size_t k = 0; k < face.nodes.size(); ++k)
                skin_edges.insert(
                    std::minmax(face.nodes[k], face.nodes[(k + 1) % face.nodes.size()]));
    struct Border {
        std::uint32_t a, b;
        std::size_t face;
    };
    std::vector<Border> border;
    std::map<std::uint32_t, Vec3> outward;
    double reach = 2 * s.edge_length;
    for (const auto& [i, corners] : s.loops) {
        const auto& nodes = mesh.faces[std::size_t(s.faces[i])].nodes;
        Vec3 centre = Vec3::Zero();
        for (const Index n : nodes)
            centre += mesh.rest[std::size_t(n)] / double(nodes.size());
        for (const Index n : nodes)
            reach = std::max(reach, 2 * (mesh.rest[std::size_t(n)] - centre).norm());
        for (std::size_t k = 0; k < nodes.size(); ++k) {
            const Index na = nodes[k], nb = nodes[(k + 1) % nodes.size()];
            if (!skin_edges.count(std::minmax(na, nb)))
                continue;
            const std::uint32_t a = welded.at(na), b = welded.at(nb);
            if (a == b)
                continue;
            const Vec3 &pa = s.cut.points[a], &pb = s.cut.points[b];
            Vec3 d = (pb - pa).cross(s.normal[i]);
            if (d.dot(0.5 * (pa + pb) - centre) < 0)
                d = -d;
            if (!(d.norm() > 0))
                continue;
            d.normalize();
            for (const std::uint32_t w : { a, b })
                outward.emplace(w, Vec3::Zero()).first->second += d;
            border.push_back({ a, b, i });
        }
    }
    // Each corner reaches out as far as its shortest border edge is long (and no further
    // than a face's size): the skin lies within about a cell of the mesh's boundary, and
    // shorter reaches keep the quads at a reflex corner from folding over each other.
    std::map<std::uint32_t, double> shortest;
    for (const Border& e : border) {
        const double length = (s.cut.points[e.a] - s.cut.points[e.b]).norm();
        for (const std::uint32_t w : { e.a, e.b }) {
            const auto [it, fresh] = shortest.emplace(w, length);
            if (!fresh)
                it->second = std::min(it->second, length);
        }
    }
    std::map<std::uint32_t, std::uint32_t> moved;
    for (const auto& [w, d] : outward) {
        if (!(d.norm() > 1e-6))
            continue;
        if (s.front.count(key_of(s.cut.points[w])))
            s.front.insert(
                key_of(s.cut.points[w] + std::min(reach, shortest.at(w)) * d.normalized()));
        moved[w] = std::uint32_t(s.cut.points.size());
        s.cut.points.push_back(s.cut.points[w] + std::min(reach, shortest.at(w)) * d.normalized());
    }
    for (const Border& e : border) {
        const auto ia = moved.find(e.a), ib = moved.find(e.b);
        if (ia == moved.end() || ib == moved.end())
            continue;
        s.loops.emplace_back(
            e.face, std::vector<std::uint32_t> { e.a, ia->second, ib->second, e.b });
        ++s.extension_quads;
    }
}

} // namespace

CutSurface build_cut_surface(const mesh::Mesh& mesh, const std::vector<Index>& cut_faces) {
    CutSurface s;
    Box bounds;
    // A slit inside one cell (the blade entered the cell and stopped): its two faces belong to
    // the cell and have the same nodes, so the material there has not parted; the skin is not
    // split across it (both copies would move alike) and it has no lips.
    std::map<std::pair<Index, std::vector<Index>>, int> in_cell;
    auto slit_key = [&](const mesh::Face& face) {
        std::vector<Index> nodes = face.nodes;
        std::sort(nodes.begin(), nodes.end());
        return std::make_pair(face.owner, std::move(nodes));
    };
    auto usable = [&](Index f) {
        if (f < 0 || f >= mesh.num_faces())
            return false;
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        return face.boundary() && face.tag == mesh::FaceTag::Cut && face.nodes.size() >= 3;
    };
    for (const Index f : cut_faces)
        if (usable(f))
            ++in_cell[slit_key(mesh.faces[std::size_t(f)])];
    for (const Index f : cut_faces) {
        if (!usable(f))
            continue;
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        if (in_cell[slit_key(face)] > 1) {
            ++s.slit_faces;
            continue;
        }
        std::vector<Vec3> loop;
        for (const Index n : face.nodes) {
            loop.push_back(mesh.rest[std::size_t(n)]);
            bounds.add(loop.back());
        }
        s.faces.push_back(f);
        s.normal.push_back(geometry::polygon_normal(loop));
    }
    if (s.faces.empty())
        return s;
    s.tolerance = 1e-9 * (bounds.hi - bounds.lo).norm();

    // 1. Sides.
    const std::size_t nf = s.faces.size();
    std::vector<std::size_t> parent(nf);
    std::vector<char> parity(nf, 0); // relative to the parent
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    auto side_of = [&](std::size_t i) {
        char p = 0;
        while (parent[i] != i) {
            p ^= parity[i];
            i = parent[i];
        }
        return std::make_pair(i, p);
    };
    auto unite = [&](std::size_t a, std::size_t b, char differ) {
        const auto [ra, pa] = side_of(a);
        const auto [rb, pb] = side_of(b);
        if (ra != rb) {
            parent[rb] = ra;
            parity[rb] = char(pa ^ pb ^ differ);
        }
    };
    {
        std::map<std::pair<Index, Index>, std::size_t> edge_face;
        std::map<std::vector<Key>, std::size_t> polygon_face;
        for (std::size_t i = 0; i < nf; ++i) {
            const mesh::Face& face = mesh.faces[std::size_t(s.faces[i])];
            std::vector<Key> sorted;
            for (std::size_t k = 0; k < face.nodes.size(); ++k) {
                const Index a = face.nodes[k], b = face.nodes[(k + 1) % face.nodes.size()];
                sorted.push_back(key_of(mesh.rest[std::size_t(a)]));
                const auto [it, fresh] = edge_face.emplace(std::minmax(a, b), i);
                if (!fresh)
                    unite(it->second, i, s.normal[it->second].dot(s.normal[i]) < 0);
            }
            std::sort(sorted.begin(), sorted.end());
            const auto [it, fresh] = polygon_face.emplace(std::move(sorted), i);
            if (!fresh)
                unite(it->second, i, 1);
        }
    }
    s.side.resize(nf);
    for (std::size_t i = 0; i < nf; ++i)
        s.side[i] = side_of(i).second;

    // 2. Welded corners (all faces: the other side's corners may lie on this side's edges).
    const double tol = s.tolerance;
    PointGrid fine(2 * tol);
    std::map<Index, std::uint32_t> welded; // node -> cut point
    for (std::size_t i = 0; i < nf; ++i)
        for (const Index n : mesh.faces[std::size_t(s.faces[i])].nodes) {
            if (welded.count(n))
                continue;
            const Vec3& p = mesh.rest[std::size_t(n)];
            std::uint32_t found = ~0u;
            fine.visit(p - Vec3::Constant(tol), p + Vec3::Constant(tol), [&](std::uint32_t id) {
                if (found == ~0u && (s.cut.points[id] - p).norm() <= tol)
                    found = id;
            });
            if (found == ~0u) {
                found = std::uint32_t(s.cut.points.size());
                s.cut.points.push_back(p);
                fine.insert(p, found);
            }
            welded.emplace(n, found);
        }
    for (std::size_t i = 0; i < nf; ++i)
        for (const Index n : mesh.faces[std::size_t(s.faces[i])].nodes)
            s.side_node[s.side[i]].emplace(key_of(s.cut.points[welded.at(n)]), n);
    for (const auto& [key, node] : s.side_node[0])
        if (const auto it = s.side_node[1].find(key);
            it != s.side_node[1].end() && it->second == node)
            s.front.insert(key);

    // 3. Side 0's loops of welded corners, triangulated with the corners on their edges.
    double edge_sum = 0;
    std::size_t edges = 0;
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& nodes = mesh.faces[std::size_t(s.faces[i])].nodes;
        for (std::size_t k = 0; k < nodes.size(); ++k, ++edges)
            edge_sum += (mesh.rest[std::size_t(nodes[k])]
                - mesh.rest[std::size_t(nodes[(k + 1) % nodes.size()])])
                            .norm();
    }
    s.edge_length = std::max(edge_sum / double(std::max<std::size_t>(edges, 1)), 4 * tol);
    for (std::size_t i = 0; i < nf; ++i) {
        if (s.side[i] != 0)
            continue;
        std::vector<std::uint32_t> corners;
        for (const Index n : mesh.faces[std::size_t(s.faces[i])].nodes) {
            const std::uint32_t w = welded.at(n);
            if (corners.empty() || corners.back() != w)
                corners.push_back(w);
        }
        while (corners.size() > 1 && corners.front() == corners.back())
            corners.pop_back();
        if (corners.size() >= 3)
            s.loops.emplace_back(i, std::move(corners));
    }
    extend_past_the_mesh(s, mesh, welded);
    triangulate(s);
    return s;
}

void fit_to_skin(CutSurface& s, const std::vector<Vec3>& points) {
    if (s.cut.points.empty() || points.empty())
        return;
    const double tol = s.tolerance;
    PointGrid grid(2 * tol);
    for (std::uint32_t i = 0; i < points.size(); ++i)
        grid.insert(points[i], i);
    std::map<Key, Key> moved;
    std::vector<char> taken(points.size(), 0);
    for (Vec3& p : s.cut.points) {
        std::uint32_t found = ~0u;
        double nearest = tol;
        grid.visit(p - Vec3::Constant(tol), p + Vec3::Constant(tol), [&](std::uint32_t id) {
            const double d = (points[id] - p).norm();
            if (d <= nearest) {
                nearest = d;
                found = id;
            }
        });
        if (found == ~0u)
            continue;
        taken[found] = 1;
        if (points[found] == p)
            continue;
        moved.emplace(key_of(p), key_of(points[found]));
        p = points[found];
    }
    for (auto& side : s.side_node) {
        std::map<Key, Index> rekeyed;
        for (const auto& [key, node] : side) {
            const auto it = moved.find(key);
            rekeyed.emplace(it == moved.end() ? key : it->second, node);
        }
        side = std::move(rekeyed);
    }
    // Skin vertices near the cut become cut points; those on no loop edge are dropped again.
    const std::size_t corners = s.cut.points.size();
    Box near = s.all;
    near.lo -= Vec3::Constant(tol);
    near.hi += Vec3::Constant(tol);
    for (std::uint32_t i = 0; i < points.size(); ++i)
        if (!taken[i] && (points[i].array() >= near.lo.array()).all()
            && (points[i].array() <= near.hi.array()).all())
            s.cut.points.push_back(points[i]);
    triangulate(s);
    std::vector<std::uint32_t> index(s.cut.points.size(), ~0u);
    std::iota(index.begin(), index.begin() + std::ptrdiff_t(corners), 0u);
    std::vector<Vec3> kept(s.cut.points.begin(), s.cut.points.begin() + std::ptrdiff_t(corners));
    for (auto& tri : s.cut.triangles)
        for (std::uint32_t& v : tri) {
            if (index[v] == ~0u) {
                index[v] = std::uint32_t(kept.size());
                kept.push_back(s.cut.points[v]);
            }
            v = index[v];
        }
    s.cut.points = std::move(kept);
}

bool on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double tol) {
    const Vec3 n = (b - a).cross(c - a);
    const double area2 = n.norm();
    if (!(area2 > 0) || std::abs((p - a).dot(n)) > tol * area2)
        return false;
    const double eps = -1e-9 * area2 * area2;
    return (b - a).cross(p - a).dot(n) >= eps && (c - b).cross(p - b).dot(n) >= eps
        && (a - c).cross(p - c).dot(n) >= eps;
}

bool meets_earlier_cut(const CutSurface& s, const mesh::Mesh& mesh,
    const std::vector<Index>& fresh_faces,
    const std::map<Key, std::vector<std::uint32_t>>& seam_vertices) {
    // New faces meeting an earlier cut's faces (a stroke carried on): the two cut surfaces, and
    // their extensions past the mesh's skin, would be triangulated and extended each on its
    // own, and their lips would overlap where they meet.
    const std::set<Index> fresh(fresh_faces.begin(), fresh_faces.end());
    std::set<Index> nodes;
    for (const Index f : s.faces)
        for (const Index n : mesh.faces[std::size_t(f)].nodes)
            nodes.insert(n);
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        if (face.boundary() && face.tag == mesh::FaceTag::Cut && !fresh.count(f)
            && std::any_of(
                face.nodes.begin(), face.nodes.end(), [&](Index n) { return nodes.count(n) > 0; }))
            return true;
    }
    // A Cut face that grew (the blade carried on through a cell it had only entered): the skin
    // is already split along the earlier faces, which the new ones cover only up to rounding;
    // corefining again would cross the old seams at rounding-sized angles.
    constexpr double kOnCut = 1e-9; // [m], far above rounding, far below any triangle
    for (const auto& [key, ids] : seam_vertices) {
        const Vec3 p(key[0], key[1], key[2]);
        Box at;
        at.add(p);
        if (!at.overlaps(s.all, kOnCut))
            continue;
        for (std::size_t t = 0; t < s.cut.triangles.size(); ++t) {
            const auto& tri = s.cut.triangles[t];
            if (at.overlaps(s.triangle_box[t], kOnCut)
                && on_triangle(
                    p, s.cut.points[tri[0]], s.cut.points[tri[1]], s.cut.points[tri[2]], kOnCut))
                return true;
        }
    }
    return false;
}

} // namespace polycut::embed::detail
