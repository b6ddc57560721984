// The CGAL half of splitting an embedded surface along a cut (corefine.hpp): exact
// constructions (Epeck), so a point where the surface crosses the cut is one exact point for
// both meshes and rounds to the same double in each.
#include "corefine.hpp"

#include "polycut/common/error.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>
#include <cmath>
#include <map>
#include <string>

namespace polycut::embed::detail {

namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = EK::Point_3;
using SMesh = CGAL::Surface_mesh<Point>;
using Face = SMesh::Face_index;
using OriginMap = SMesh::Property_map<Face, std::uint32_t>;

SMesh to_cgal(const TriangleSet& s, const char* what) {
    SMesh m;
    std::vector<SMesh::Vertex_index> v;
    v.reserve(s.points.size());
    for (const Vec3& p : s.points)
        v.push_back(m.add_vertex(Point(p.x(), p.y(), p.z())));
    OriginMap origin = m.add_property_map<Face, std::uint32_t>("f:origin", 0).first;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
        const auto& tri = s.triangles[t];
        const Face f = m.add_face(v[tri[0]], v[tri[1]], v[tri[2]]);
        if (f == SMesh::null_face())
            throw Error("embedded",
                std::string("the ") + what + " triangle " + std::to_string(t)
                    + " makes the patch non-manifold");
        origin[f] = std::uint32_t(t);
    }
    return m;
}

/// Gives the pieces of a split face the origin of the face they were split from.
struct OriginVisitor : CGAL::Polygon_mesh_processing::Corefinement::Default_visitor<SMesh> {
    std::uint32_t current = 0;
    void before_subface_creations(Face f_old, SMesh& tm) {
        current = tm.property_map<Face, std::uint32_t>("f:origin").first[f_old];
    }
    void after_subface_created(Face f_new, SMesh& tm) {
        tm.property_map<Face, std::uint32_t>("f:origin").first[f_new] = current;
    }
};

TriangleSet from_cgal(const SMesh& m) {
    TriangleSet out;
    out.points.reserve(m.number_of_vertices());
    for (const auto v : m.vertices()) {
        // Rounded from the exact value: two meshes holding the same exact point (a crossing)
        // get the same doubles, however far each lazy number's approximation was refined.
        const Point& p = m.point(v);
        out.points.emplace_back(CGAL::to_double(CGAL::exact(p.x())),
            CGAL::to_double(CGAL::exact(p.y())), CGAL::to_double(CGAL::exact(p.z())));
    }
    const OriginMap origin = m.property_map<Face, std::uint32_t>("f:origin").first;
    for (const auto f : m.faces()) {
        std::array<std::uint32_t, 3> t {};
        int k = 0;
        for (const auto v : CGAL::vertices_around_face(m.halfedge(f), m))
            t[std::size_t(k++)] = std::uint32_t(v.idx());
        out.triangles.push_back(t);
        out.origin.push_back(origin[f]);
    }
    return out;
}

/// Drops the triangles with a repeated corner after `index` renumbered the vertices.
void renumber(TriangleSet& s, const std::vector<std::uint32_t>& index) {
    std::size_t kept = 0;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
        auto tri = s.triangles[t];
        for (std::uint32_t& v : tri)
            v = index[v];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
            continue;
        s.triangles[kept] = tri;
        s.origin[kept] = s.origin[t];
        ++kept;
    }
    s.triangles.resize(kept);
    s.origin.resize(kept);
}

/// Welds the points of both meshes that lie within `tol` of each other (two exact points a
/// rounding apart: a skin edge on a line where the cut folds by a rounding-sized angle, a cut
/// node 1e-19 m off a skin vertex an earlier split made): in each mesh they become its first
/// vertex of the cluster, at the cluster's first position (the patch's input vertices come
/// first, so the skin keeps its vertices where they were), and the triangles that collapse are
/// dropped. Returns the patch's old -> new index.
std::vector<std::uint32_t> weld_near(TriangleSet& patch, TriangleSet& cut, double tol) {
    const double h = std::max(2 * tol, 1e-300);
    using Cell = std::array<long long, 3>;
    auto cell_of = [&](const Vec3& p) {
        return Cell { (long long)std::floor(p.x() / h), (long long)std::floor(p.y() / h),
            (long long)std::floor(p.z() / h) };
    };
    std::map<Cell, std::vector<std::uint32_t>> grid; // cluster ids
    std::vector<Vec3> where; // each cluster's position
    auto cluster_of = [&](const Vec3& p) {
        const Cell c = cell_of(p);
        for (long long i = -1; i <= 1; ++i)
            for (long long j = -1; j <= 1; ++j)
                for (long long k = -1; k <= 1; ++k)
                    if (const auto it = grid.find({ c[0] + i, c[1] + j, c[2] + k });
                        it != grid.end())
                        for (const std::uint32_t id : it->second)
                            if ((where[id] - p).norm() <= tol)
                                return id;
        where.push_back(p);
        grid[c].push_back(std::uint32_t(where.size() - 1));
        return std::uint32_t(where.size() - 1);
    };
    auto weld = [&](TriangleSet& s) {
        std::vector<std::uint32_t> index(s.points.size());
        std::map<std::uint32_t, std::uint32_t> first; // cluster -> vertex of s
        bool any = false;
        for (std::uint32_t v = 0; v < s.points.size(); ++v) {
            const std::uint32_t c = cluster_of(s.points[v]);
            const auto [it, fresh] = first.emplace(c, v);
            index[v] = it->second;
            any = any || !fresh || s.points[v] != where[c];
            s.points[v] = where[c];
        }
        if (any)
            renumber(s, index);
        return index;
    };
    std::vector<std::uint32_t> index = weld(patch);
    weld(cut);
    return index;
}

} // namespace

Corefined corefine_patch(const TriangleSet& patch, const TriangleSet& cut,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& constrained, double tol) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    SMesh a = to_cgal(patch, "surface");
    SMesh b = to_cgal(cut, "cut");
    auto ecm = a.add_property_map<SMesh::Edge_index, bool>("e:constrained", false).first;
    for (const auto& [u, v] : constrained) {
        const auto h = a.halfedge(SMesh::Vertex_index(u), SMesh::Vertex_index(v));
        if (h != SMesh::null_halfedge())
            ecm[a.edge(h)] = true;
    }
    OriginVisitor visitor;
    try {
        PMP::corefine(a, b, CGAL::parameters::edge_is_constrained_map(ecm).visitor(visitor),
            CGAL::parameters::default_values());
    } catch (const std::exception& e) {
        throw Error(
            "embedded", std::string("corefining the surface with the cut failed: ") + e.what());
    }
    Corefined out;
    // Surface_mesh keeps the indices of existing vertices and appends new ones (no removals
    // happen in corefinement), so from_cgal's order is the index order.
    out.patch = from_cgal(a);
    out.cut = from_cgal(b);
    const std::vector<std::uint32_t> patch_index = weld_near(out.patch, out.cut, tol);
    for (const auto e : a.edges())
        if (ecm[e]) {
            std::uint32_t u = patch_index[a.vertex(e, 0).idx()],
                          v = patch_index[a.vertex(e, 1).idx()];
            if (u == v)
                continue;
            if (u > v)
                std::swap(u, v);
            out.constrained.emplace_back(u, v);
        }
    return out;
}

} // namespace polycut::embed::detail
