// Alpha_wrap_3 (CGAL 5.5) of a triangle soup: a watertight, 2-manifold, self-intersection-free
// surface strictly outside the input at a chosen offset. Its own translation unit: the wrapper
// instantiates a Delaunay triangulation with exact constructions and compiles slowly.
#include "surface_prepare.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>
#include <array>
#include <vector>

namespace polycut::meshing::detail {

SurfaceMesh alpha_wrap(const SurfaceMesh& s, double alpha, double offset) {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Point = Kernel::Point_3;
    using CgalMesh = CGAL::Surface_mesh<Point>;
    std::vector<Point> points;
    points.reserve(s.positions.size());
    for (const Vec3& p : s.positions)
        points.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::array<std::size_t, 3>> faces;
    faces.reserve(s.triangles.size());
    for (const auto& t : s.triangles)
        faces.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    CgalMesh wrap;
    CGAL::alpha_wrap_3(points, faces, alpha, offset, wrap);
    // The wrap is outward already; orienting costs little and does not rely on it.
    CGAL::Polygon_mesh_processing::orient_to_bound_a_volume(wrap);

    std::vector<Index> id(wrap.number_of_vertices() + wrap.number_of_removed_vertices(), kNone);
    SurfaceMesh out;
    for (auto v : wrap.vertices()) {
        id[std::size_t(v.idx())] = Index(out.positions.size());
        const Point& p = wrap.point(v);
        out.positions.emplace_back(p.x(), p.y(), p.z());
    }
    for (auto f : wrap.faces()) {
        std::array<Index, 3> tri {};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(wrap.halfedge(f), wrap))
            if (k < 3)
                tri[std::size_t(k++)] = id[std::size_t(v.idx())];
        out.triangles.push_back(tri);
    }
    return out;
}

} // namespace polycut::meshing::detail
