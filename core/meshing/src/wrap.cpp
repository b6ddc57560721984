// Alpha_wrap_3 (CGAL 5.5) of a triangle soup: a watertight, 2-manifold, self-intersection-free
// surface strictly outside the input at a chosen offset. Its own translation unit: the wrapper
// instantiates a Delaunay triangulation with exact constructions and compiles slowly.
#include "polycut/common/error.hpp"
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
    // Alpha_wrap_3 projects points onto the input's triangles in doubles. On a triangle whose
    // edges or area underflow (squared lengths below 1e-200: a cube with corners collapsed to
    // ~1e-312, tests/fuzz corpus regression_pmp_smoothing_nan) the projection is NaN and the
    // exact predicates after it abort the process (GMP raises SIGFPE on mpq_set_d(NaN)); with
    // coordinates past 1e100 m the squared distances overflow the same way. Such triangles are
    // left out of the soup (a wrap closes over what is missing); such coordinates are refused.
    for (const Vec3& p : s.positions)
        if (!(p.cwiseAbs().maxCoeff() <= 1e100))
            throw InputError(
                "surface", "a vertex lies beyond 1e100 m from the origin: too far to wrap");
    std::vector<std::array<std::size_t, 3>> faces;
    faces.reserve(s.triangles.size());
    for (const auto& t : s.triangles) {
        const Vec3 &a = s.positions[std::size_t(t[0])], &b = s.positions[std::size_t(t[1])],
                   &c = s.positions[std::size_t(t[2])];
        const bool usable = (b - a).squaredNorm() >= 1e-200 && (c - b).squaredNorm() >= 1e-200
            && (a - c).squaredNorm() >= 1e-200 && (b - a).cross(c - a).squaredNorm() >= 1e-200;
        if (usable)
            faces.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    }
    if (faces.empty())
        throw InputError("surface",
            "no triangle of the surface is large enough to wrap (every one "
            "has an edge or an area below 1e-100 m)");
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
