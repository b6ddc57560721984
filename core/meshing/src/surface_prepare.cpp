// Checks a triangle surface before meshing and orients it outward with CGAL's
// Polygon_mesh_processing (orient_polygon_soup, does_self_intersect, orient_to_bound_a_volume).
#include "surface_prepare.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <cmath>
#include <cstddef>
#include <vector>

namespace polycut::meshing {

namespace detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMeshCgal = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

} // namespace

std::string soup_problem(const SurfaceMesh& s) {
    if (s.triangles.empty())
        return "no triangles";
    for (std::size_t v = 0; v < s.positions.size(); ++v)
        if (!s.positions[v].allFinite())
            return "vertex " + std::to_string(v) + " has a non-finite coordinate";
    const auto n = Index(s.positions.size());
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
        const auto& tri = s.triangles[t];
        for (Index v : tri)
            if (v < 0 || v >= n)
                return "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v)
                    + ", out of range [0, " + std::to_string(n) + ")";
    }
    return {};
}

std::string prepare_closed_surface(SurfaceMesh& s) {
    if (std::string problem = soup_problem(s); !problem.empty())
        return problem;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
        const auto& tri = s.triangles[t];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            return "triangle " + std::to_string(t) + " repeats a vertex";
    }
    // Only the vertices a triangle uses, in their order: a file may list more, and those would
    // be isolated vertices of the Surface_mesh, whose null halfedge orient_to_bound_a_volume()
    // follows out of bounds (CGAL 5.5; found by tests/fuzz/fuzz_surface_readers, corpus
    // regression_unused_vertices).
    std::vector<Index> soup_id(s.positions.size(), kNone);
    for (const auto& t : s.triangles)
        for (Index v : t)
            soup_id[std::size_t(v)] = 0;
    std::vector<Point> points;
    for (std::size_t v = 0; v < s.positions.size(); ++v)
        if (soup_id[v] == 0) {
            soup_id[v] = Index(points.size());
            points.emplace_back(s.positions[v].x(), s.positions[v].y(), s.positions[v].z());
        }
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(s.triangles.size());
    for (const auto& t : s.triangles)
        polygons.push_back({ std::size_t(soup_id[std::size_t(t[0])]),
            std::size_t(soup_id[std::size_t(t[1])]), std::size_t(soup_id[std::size_t(t[2])]) });
    // orient_polygon_soup duplicates vertices where the soup is not an orientable manifold
    // and then returns false.
    if (!PMP::orient_polygon_soup(points, polygons))
        return "not an orientable 2-manifold (non-manifold edge or vertex, or a Moebius-like "
               "orientation conflict)";
    SurfaceMeshCgal sm;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
    std::size_t border_edges = 0;
    for (auto h : sm.halfedges())
        if (sm.is_border(h))
            ++border_edges;
    if (border_edges > 0)
        return "not closed: " + std::to_string(border_edges) + " border edges";
    if (PMP::does_self_intersect(sm))
        return "self-intersecting";
    PMP::orient_to_bound_a_volume(sm);

    // Read back, keeping only vertices used by a face, in their original order.
    std::vector<Index> id(sm.number_of_vertices(), kNone);
    for (auto f : sm.faces())
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
            id[std::size_t(v.idx())] = 0;
    SurfaceMesh out;
    for (auto v : sm.vertices())
        if (id[std::size_t(v.idx())] == 0) {
            id[std::size_t(v.idx())] = Index(out.positions.size());
            const Point& p = sm.point(v);
            out.positions.emplace_back(p.x(), p.y(), p.z());
        }
    for (auto f : sm.faces()) {
        std::array<Index, 3> tri {};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
            tri[std::size_t(k++)] = id[std::size_t(v.idx())];
        out.triangles.push_back(tri);
    }
    s = std::move(out);
    return {};
}

} // namespace detail

std::string closed_surface_problem(const SurfaceMesh& surface) {
    SurfaceMesh copy = surface;
    return detail::prepare_closed_surface(copy);
}

} // namespace polycut::meshing
