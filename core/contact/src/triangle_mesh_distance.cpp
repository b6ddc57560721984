// Signed distance to a closed triangle surface (triangle_mesh_distance.hpp): CGAL's AABB tree
// gives the closest point, Side_of_triangle_mesh the sign. The only CGAL translation unit of
// core/contact.
#include "polycut/contact/triangle_mesh_distance.hpp"

#include "polycut/common/error.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

namespace polycut::contact {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Inside = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>;

Vec3 to_vec(const Point& p) {
    return { p.x(), p.y(), p.z() };
}
} // namespace

struct TriangleMeshDistance::Impl {
    SurfaceMesh mesh;
    std::unique_ptr<Tree> tree;
    std::unique_ptr<Inside> inside;
};

TriangleMeshDistance::TriangleMeshDistance(
    std::vector<Vec3> positions, const std::vector<std::array<Index, 3>>& triangles)
    : m_impl(std::make_unique<Impl>()) {
    if (positions.empty() || triangles.empty())
        throw InputError("mesh", "the surface has no triangles");
    std::vector<SurfaceMesh::Vertex_index> vertices;
    vertices.reserve(positions.size());
    m_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    m_hi = -m_lo;
    for (const Vec3& p : positions) {
        vertices.push_back(m_impl->mesh.add_vertex(Point(p.x(), p.y(), p.z())));
        m_lo = m_lo.cwiseMin(p);
        m_hi = m_hi.cwiseMax(p);
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (const Index v : tri)
            if (v < 0 || std::size_t(v) >= positions.size())
                throw InputError("mesh",
                    "triangle " + std::to_string(t) + " names vertex " + std::to_string(v) + " of "
                        + std::to_string(positions.size()));
        if (m_impl->mesh.add_face(vertices[std::size_t(tri[0])], vertices[std::size_t(tri[1])],
                vertices[std::size_t(tri[2])])
            == SurfaceMesh::null_face())
            throw InputError(
                "mesh", "triangle " + std::to_string(t) + " makes the surface non-manifold");
        const Vec3& a = positions[std::size_t(tri[0])];
        const Vec3& b = positions[std::size_t(tri[1])];
        const Vec3& c = positions[std::size_t(tri[2])];
        m_volume += a.dot(b.cross(c)) / 6.0;
    }
    m_num_triangles = triangles.size();
    m_impl->tree = std::make_unique<Tree>(
        faces(m_impl->mesh).first, faces(m_impl->mesh).second, m_impl->mesh);
    m_impl->tree->accelerate_distance_queries();
    m_impl->inside = std::make_unique<Inside>(*m_impl->tree);
    m_volume = std::abs(m_volume);
}

TriangleMeshDistance::~TriangleMeshDistance() = default;

double TriangleMeshDistance::signed_distance(const Vec3& p, Vec3& normal) const {
    const Point q(p.x(), p.y(), p.z());
    const auto [closest, face] = m_impl->tree->closest_point_and_primitive(q);
    const Vec3 c = to_vec(closest);
    const double d = (p - c).norm();
    const bool in = (*m_impl->inside)(q) == CGAL::ON_BOUNDED_SIDE;
    // Outward direction: from the closest point to p outside, from p to it inside; on the
    // surface itself the face normal (outward for an outward-oriented surface).
    const auto h = m_impl->mesh.halfedge(face);
    const Vec3 a = to_vec(m_impl->mesh.point(m_impl->mesh.source(h)));
    const Vec3 b = to_vec(m_impl->mesh.point(m_impl->mesh.target(h)));
    const Vec3 e = to_vec(m_impl->mesh.point(m_impl->mesh.target(m_impl->mesh.next(h))));
    Vec3 face_normal = (b - a).cross(e - a);
    face_normal = face_normal.norm() > 0 ? Vec3(face_normal.normalized()) : Vec3::UnitZ();
    const double scale = (m_hi - m_lo).norm();
    if (d > 1e-12 * scale)
        normal = (in ? c - p : p - c) / d;
    else
        normal = face_normal;
    return in ? -d : d;
}

} // namespace polycut::contact
