// The CGAL half of splitting an embedded surface along a cut (corefine.hpp): exact
// constructions (Epeck), so a point where the surface crosses the cut is one exact point for
// both meshes and rounds to the same double in each.
#include "corefine.hpp"

#include "polycut/common/error.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>
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

} // namespace

Corefined corefine_patch(const TriangleSet& patch, const TriangleSet& cut,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& constrained) {
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
    for (const auto e : a.edges())
        if (ecm[e]) {
            std::uint32_t u = std::uint32_t(a.vertex(e, 0).idx()),
                          v = std::uint32_t(a.vertex(e, 1).idx());
            if (u > v)
                std::swap(u, v);
            out.constrained.emplace_back(u, v);
        }
    return out;
}

} // namespace polycut::embed::detail
