// The CGAL half of hexahedral slicing (hex_slice_grid.hpp): the surface corefined with one
// large rectangle per inner grid plane, with exact constructions (Epeck), so that a point where
// the surface crosses a grid plane or a grid line is the same exact point for every cube that
// sees it, and rounds to the same double.
#include "hex_slice_grid.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <cmath>
#include <string>

namespace polycut::meshing::detail {

namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using EPoint = EK::Point_3;
using EMesh = CGAL::Surface_mesh<EPoint>;
using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
using IMesh = CGAL::Surface_mesh<IK::Point_3>;

template <class MeshT> MeshT to_cgal(const SurfaceMesh& s) {
    using Point = typename MeshT::Point;
    MeshT m;
    std::vector<typename MeshT::Vertex_index> v;
    v.reserve(s.positions.size());
    for (const Vec3& p : s.positions)
        v.push_back(m.add_vertex(Point(p.x(), p.y(), p.z())));
    for (const auto& t : s.triangles)
        m.add_face(v[std::size_t(t[0])], v[std::size_t(t[1])], v[std::size_t(t[2])]);
    return m;
}

/// Where exact coordinate x lies among the planes: returns the plane index if x is on one,
/// else -1 with `slab` set (planes[slab] < x < planes[slab + 1]).
int locate(const EK::FT& x, const std::vector<double>& planes, int& slab) {
    const int n = int(planes.size()) - 1;
    const double h = planes[1] - planes[0];
    int i = int(std::floor((CGAL::to_double(x) - planes[0]) / h));
    i = std::clamp(i, 0, n - 1);
    while (i > 0 && x < EK::FT(planes[std::size_t(i)]))
        --i;
    while (i < n - 1 && !(x < EK::FT(planes[std::size_t(i + 1)])))
        ++i;
    if (x == EK::FT(planes[std::size_t(i)])) {
        slab = -1;
        return i;
    }
    slab = i;
    return -1;
}

/// One triangle covering the plane x[axis] = c over `box` (and more). A single triangle: an
/// inner edge of the splitter would put extra vertices on the surface where it crosses it.
EMesh plane_triangle(int axis, double c, const CGAL::Bbox_3& box) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const double lo1 = box.min(a1) - 1, lo2 = box.min(a2) - 1;
    const double span = (box.max(a1) - box.min(a1)) + (box.max(a2) - box.min(a2)) + 4;
    auto corner = [&](double u, double v) {
        std::array<double, 3> p {};
        p[std::size_t(axis)] = c;
        p[std::size_t(a1)] = u;
        p[std::size_t(a2)] = v;
        return EPoint(p[0], p[1], p[2]);
    };
    EMesh m;
    m.add_face(m.add_vertex(corner(lo1, lo2)), m.add_vertex(corner(lo1 + span, lo2)),
        m.add_vertex(corner(lo1, lo2 + span)));
    return m;
}

/// Throws DegenerateGrid if a vertex of `m` lies exactly on one of the planes of `axis`.
void check_off_planes(const EMesh& m, int axis, const std::vector<double>& planes) {
    for (auto v : m.vertices()) {
        int slab = 0;
        if (locate(m.point(v)[axis], planes, slab) >= 0)
            throw DegenerateGrid(
                "a surface vertex lies on a grid plane of axis " + std::to_string(axis));
    }
}

} // namespace

SlicedSurface slice_surface(const SurfaceMesh& surface, const SliceGrid& grid) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    EMesh tm = to_cgal<EMesh>(surface);
    const CGAL::Bbox_3 box = PMP::bbox(tm);
    for (int axis = 0; axis < 3; ++axis) {
        const std::vector<double>& planes = grid.planes[std::size_t(axis)];
        // Vertices made by earlier axes lie on their planes; none may lie on this axis' planes.
        check_off_planes(tm, axis, planes);
        for (std::size_t i = 1; i + 1 < planes.size(); ++i) {
            if (!(planes[i] > box.min(axis) && planes[i] < box.max(axis)))
                continue;
            EMesh splitter = plane_triangle(axis, planes[i], box);
            PMP::corefine(tm, splitter, CGAL::parameters::default_values(),
                CGAL::parameters::do_not_modify(true));
        }
    }

    SlicedSurface out;
    std::vector<Index> id(tm.number_of_vertices() + tm.number_of_removed_vertices(), kNone);
    for (auto v : tm.vertices()) {
        const EPoint& p = tm.point(v);
        std::array<int, 3> plane {}, slab {};
        int on = 0;
        for (int a = 0; a < 3; ++a) {
            plane[std::size_t(a)] = locate(p[a], grid.planes[std::size_t(a)], slab[std::size_t(a)]);
            on += plane[std::size_t(a)] >= 0;
        }
        if (on == 3)
            throw DegenerateGrid("the surface passes through a grid corner");
        id[std::size_t(v.idx())] = Index(out.points.size());
        out.points.emplace_back(
            CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
        out.plane.push_back(plane);
        out.slab.push_back(slab);
    }
    for (auto f : tm.faces()) {
        std::array<Index, 3> t {};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(tm.halfedge(f), tm))
            t[std::size_t(k++)] = id[std::size_t(v.idx())];
        std::array<int, 3> cube {};
        for (std::size_t a = 0; a < 3; ++a) {
            // The slab of any vertex off the axis' planes; if all are on planes, the lower one
            // (a triangle spanning one slab from plane i to plane i + 1).
            int slab = -1, lowest = 1 << 30, highest = -1;
            for (Index n : t) {
                const auto& pl = out.plane[std::size_t(n)];
                if (pl[a] < 0)
                    slab = out.slab[std::size_t(n)][a];
                else {
                    lowest = std::min(lowest, pl[a]);
                    highest = std::max(highest, pl[a]);
                }
            }
            if (slab < 0) {
                if (highest == lowest)
                    throw DegenerateGrid("a surface triangle lies in a grid plane");
                slab = lowest;
            }
            cube[a] = slab;
        }
        out.triangles.push_back(t);
        out.cube.push_back(cube);
    }
    return out;
}

std::vector<int> sides(const SurfaceMesh& surface, const std::vector<Vec3>& points) {
    const IMesh tm = to_cgal<IMesh>(surface);
    const CGAL::Side_of_triangle_mesh<IMesh, IK> side(tm);
    std::vector<int> out;
    out.reserve(points.size());
    for (const Vec3& p : points) {
        const CGAL::Bounded_side s = side(IK::Point_3(p.x(), p.y(), p.z()));
        if (s == CGAL::ON_BOUNDARY)
            throw DegenerateGrid("a grid corner lies on the surface");
        out.push_back(s == CGAL::ON_BOUNDED_SIDE ? 1 : -1);
    }
    return out;
}

} // namespace polycut::meshing::detail
