// Surface repair with CGAL Polygon_mesh_processing, in the order the defects depend on each
// other: soup clean-up (duplicate points, invalid and duplicate faces), orientation, stitching,
// degenerate faces, hole filling, the components option, local self-intersection removal; then
// the strict check of prepare_closed_surface(), and Alpha_wrap_3 (wrap.cpp) where asked for or
// where PMP could not make the surface clean.
#include "polycut/meshing/repair.hpp"

#include "polycut/common/error.hpp"
#include "surface_prepare.hpp"

// CGAL 5.5's experimental self-intersection removal first tries angle smoothing without its
// safety constraints; on tiny (subnormal) or collapsed patches that smoothing computes NaN
// positions and the exact predicates that follow abort the process (GMP raises SIGFPE on
// mpq_set_d(NaN)). Found by tests/fuzz/fuzz_surface_readers (corpus/surface_readers/
// regression_pmp_smoothing_nan). Without smoothing the removal cuts out and re-fills the
// intersecting patch, which only uses exact predicates on the input's points.
#define CGAL_PMP_REMOVE_SELF_INTERSECTIONS_NO_SMOOTHING
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <vector>

namespace polycut::meshing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<Point>;
using FaceIndex = CgalMesh::Face_index;
using Polygon = std::vector<std::size_t>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Signed volume enclosed by the triangles of `sm`, per connected component when `component`
/// is given (index by component id), about `origin` [m^3].
std::vector<double> component_volumes(const CgalMesh& sm,
    const CgalMesh::Property_map<FaceIndex, std::size_t>* component, std::size_t count,
    const Vec3& origin) {
    std::vector<double> volume(std::max<std::size_t>(count, 1), 0.0);
    for (FaceIndex f : sm.faces()) {
        std::array<Vec3, 3> p;
        int k = 0;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            const Point& q = sm.point(v);
            if (k < 3)
                p[std::size_t(k)] = Vec3(q.x(), q.y(), q.z()) - origin;
            ++k;
        }
        volume[component ? (*component)[f] : 0] += p[0].dot(p[1].cross(p[2])) / 6;
    }
    return volume;
}

/// The faces of `sm` as a compact surface (vertices numbered in order of their index).
SurfaceMesh to_surface(const CgalMesh& sm) {
    std::vector<Index> id(sm.number_of_vertices() + sm.number_of_removed_vertices(), kNone);
    SurfaceMesh out;
    for (auto v : sm.vertices()) {
        id[std::size_t(v.idx())] = Index(out.positions.size());
        const Point& p = sm.point(v);
        out.positions.emplace_back(p.x(), p.y(), p.z());
    }
    for (FaceIndex f : sm.faces()) {
        std::vector<Index> loop;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
            loop.push_back(id[std::size_t(v.idx())]);
        for (std::size_t k = 1; k + 1 < loop.size(); ++k)
            out.triangles.push_back({ loop[0], loop[k], loop[k + 1] });
    }
    return out;
}

Vec3 bounding_box_centre(const SurfaceMesh& s) {
    Vec3 lo = s.positions.front(), hi = lo;
    for (const Vec3& p : s.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return 0.5 * (lo + hi);
}

Index border_edge_count(const CgalMesh& sm) {
    Index n = 0;
    for (auto h : sm.halfedges())
        if (sm.is_border(h))
            ++n;
    return n;
}

std::string volume_list(const std::vector<double>& volumes) {
    std::string s;
    for (std::size_t c = 0; c < volumes.size() && c < 8; ++c) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%s%.3g", c ? ", " : "", std::abs(volumes[c]));
        s += buf;
    }
    return s + (volumes.size() > 8 ? ", ..." : "") + " m^3";
}

/// Applies the components option to `sm` (keeps all, keeps the largest by enclosed volume, or
/// throws); records the count before.
void select_components(CgalMesh& sm, ComponentsMode mode, const Vec3& origin, RepairReport& r) {
    auto component = sm.add_property_map<FaceIndex, std::size_t>("f:repair_cc", 0).first;
    const std::size_t count = PMP::connected_components(sm, component);
    r.components_in = Index(count);
    if (count > 1 && mode != ComponentsMode::Union) {
        const std::vector<double> volumes = component_volumes(sm, &component, count, origin);
        if (mode == ComponentsMode::Refuse)
            throw InputError("surface",
                "the surface has " + std::to_string(count)
                    + " connected components (enclosed volumes " + volume_list(volumes)
                    + "); set geometry.components to \"union\" or \"largest\"");
        const auto largest
            = std::size_t(std::max_element(volumes.begin(), volumes.end(), [](double a, double b) {
                  return std::abs(a) < std::abs(b);
              }) - volumes.begin());
        PMP::keep_connected_components(sm, std::vector<std::size_t> { largest }, component);
        sm.collect_garbage();
    }
    sm.remove_property_map(component);
}

CgalMesh to_cgal(const SurfaceMesh& s) {
    std::vector<Point> points;
    points.reserve(s.positions.size());
    for (const Vec3& p : s.positions)
        points.emplace_back(p.x(), p.y(), p.z());
    std::vector<Polygon> polygons;
    polygons.reserve(s.triangles.size());
    for (const auto& t : s.triangles)
        polygons.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    CgalMesh sm;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
    return sm;
}

/// The PMP part of the repair: everything but the final check and the wrap. Leaves the
/// cleaned-up mesh in `sm` and the soup to wrap (after the components option) in `to_wrap`.
class PmpRepair {
public:
    PmpRepair(const SurfaceMesh& s, const RepairOptions& o, RepairReport& r)
        : m_options(o)
        , m_report(r)
        , m_origin(bounding_box_centre(s)) {
        m_points.reserve(s.positions.size());
        for (const Vec3& p : s.positions)
            m_points.emplace_back(p.x(), p.y(), p.z());
        m_polygons.reserve(s.triangles.size());
        for (const auto& t : s.triangles)
            m_polygons.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
    }

    /// Soup clean-up, orientation, stitching, degenerate faces, holes, components.
    void clean_up(bool fill_holes) {
        m_report.duplicate_vertices_merged
            = Index(PMP::merge_duplicate_points_in_polygon_soup(m_points, m_polygons));
        const std::size_t before = m_polygons.size();
        std::erase_if(m_polygons,
            [](const Polygon& p) { return p[0] == p[1] || p[1] == p[2] || p[0] == p[2]; });
        m_report.invalid_faces_removed = Index(before - m_polygons.size());
        m_report.duplicate_faces_removed
            = Index(PMP::merge_duplicate_polygons_in_polygon_soup(m_points, m_polygons));
        PMP::repair_polygon_soup(m_points, m_polygons); // isolated points; nothing else is left
        if (m_polygons.empty())
            throw InputError("surface", "no faces left after removing invalid and duplicate ones");
        const std::size_t points_before = m_points.size();
        PMP::orient_polygon_soup(m_points, m_polygons);
        m_report.non_manifold_vertices_split = Index(m_points.size() - points_before);
        PMP::polygon_soup_to_polygon_mesh(m_points, m_polygons, m_mesh);
        m_report.volume_in = std::abs(component_volumes(m_mesh, nullptr, 1, m_origin)[0]);
        PMP::stitch_borders(m_mesh);

        std::vector<FaceIndex> degenerate;
        PMP::degenerate_faces(m_mesh, std::back_inserter(degenerate));
        if (!degenerate.empty()) {
            PMP::remove_degenerate_faces(m_mesh);
            m_mesh.collect_garbage();
        }
        m_report.degenerate_faces_removed = Index(degenerate.size());
        m_report.border_edges_in = border_edge_count(m_mesh);
        if (fill_holes)
            fill_all_holes();
        select_components(m_mesh, m_options.components, m_origin, m_report);
        // The soup a wrap would start from: clean, but before PMP's self-intersection removal.
        m_to_wrap = to_surface(m_mesh);
    }

    /// Local self-intersection removal (CGAL 5.5 experimental). Skipped when the intersecting
    /// faces belong to different components: removing them would not make a union.
    void remove_self_intersections() {
        std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
        PMP::self_intersections(m_mesh, std::back_inserter(pairs));
        m_report.self_intersections_in = Index(pairs.size());
        m_report.self_intersections_out = m_report.self_intersections_in;
        if (pairs.empty())
            return;
        auto component = m_mesh.add_property_map<FaceIndex, std::size_t>("f:repair_cc", 0).first;
        PMP::connected_components(m_mesh, component);
        const bool across = std::any_of(pairs.begin(), pairs.end(),
            [&](const auto& p) { return component[p.first] != component[p.second]; });
        m_mesh.remove_property_map(component);
        if (across || has_underflowing_edge())
            return;
        try {
            PMP::experimental::remove_self_intersections(m_mesh);
        } catch (const std::exception&) {
            return; // left for the final check (and the wrap)
        }
        m_mesh.collect_garbage();
        pairs.clear();
        PMP::self_intersections(m_mesh, std::back_inserter(pairs));
        m_report.self_intersections_out = Index(pairs.size());
        if (pairs.empty()) // removal re-fills what it cut out; close anything it left open
            fill_all_holes();
    }

    SurfaceMesh result() const { return to_surface(m_mesh); }
    const SurfaceMesh& to_wrap() const { return m_to_wrap; }

private:
    /// An edge shorter than 1e-100 (its squared length is below 1e-200, and products of two
    /// such squares are subnormal or zero). CGAL's removal measures lengths and angles in
    /// doubles: on such a surface (a cube with corners collapsed to ~1e-312, found by
    /// tests/fuzz/fuzz_surface_readers: corpus regression_pmp_*) it walked off the mesh
    /// (SEGV). The surface is then left for the final check (and the wrap).
    bool has_underflowing_edge() const {
        for (auto e : m_mesh.edges())
            if (!(CGAL::squared_distance(
                      m_mesh.point(m_mesh.vertex(e, 0)), m_mesh.point(m_mesh.vertex(e, 1)))
                    >= 1e-200))
                return true;
        return false;
    }

    void fill_all_holes() {
        std::vector<CgalMesh::Halfedge_index> cycles;
        PMP::extract_boundary_cycles(m_mesh, std::back_inserter(cycles));
        for (auto h : cycles) {
            Index edges = 0;
            for (auto e : CGAL::halfedges_around_face(h, m_mesh)) {
                (void)e;
                ++edges;
            }
            if (edges > m_options.max_hole_edges) {
                ++m_report.holes_unfilled;
                continue;
            }
            std::vector<FaceIndex> added;
            try {
                PMP::triangulate_refine_and_fair_hole(
                    m_mesh, h, std::back_inserter(added), CGAL::Emptyset_iterator());
            } catch (const std::exception&) {
                added.clear();
            }
            ++(added.empty() ? m_report.holes_unfilled : m_report.holes_filled);
        }
    }

    const RepairOptions& m_options;
    RepairReport& m_report;
    Vec3 m_origin;
    std::vector<Point> m_points;
    std::vector<Polygon> m_polygons;
    CgalMesh m_mesh;
    SurfaceMesh m_to_wrap;
};

double wrap_alpha(const RepairOptions& o, double cell_size) {
    return o.wrap_alpha > 0 ? o.wrap_alpha : cell_size;
}
double wrap_offset(const RepairOptions& o, double cell_size) {
    return o.wrap_offset > 0 ? o.wrap_offset : cell_size / 30;
}

} // namespace

SurfaceMesh repair_surface(const SurfaceMesh& surface, const RepairOptions& options,
    double cell_size, RepairReport* report_out) {
    const auto start = std::chrono::steady_clock::now();
    if (std::string problem = detail::soup_problem(surface); !problem.empty())
        throw InputError("surface", problem);
    const bool needs_size = options.mode == RepairMode::Auto || options.mode == RepairMode::Wrap;
    if (needs_size && !(std::isfinite(cell_size) && cell_size > 0)
        && !(options.wrap_alpha > 0 && options.wrap_offset > 0))
        throw InputError("cell_size", "must be finite and > 0 (it sets the wrap's alpha/offset)");
    if (!std::isfinite(options.wrap_alpha) || !std::isfinite(options.wrap_offset))
        throw InputError("wrap", "alpha and offset must be finite");

    RepairReport report;
    report.mode = options.mode;
    report.vertices_in = Index(surface.positions.size());
    report.faces_in = Index(surface.triangles.size());
    SurfaceMesh out;
    if (options.mode == RepairMode::None) {
        out = surface;
        if (std::string problem = detail::prepare_closed_surface(out); !problem.empty())
            throw InputError("surface",
                problem + " (repair is \"none\"; \"auto\", \"pmp\" or \"wrap\" would repair it)");
        report.volume_in = enclosed_volume(out);
        CgalMesh sm = to_cgal(out);
        select_components(sm, options.components, bounding_box_centre(out), report);
        out = to_surface(sm);
    } else {
        PmpRepair pmp(surface, options, report);
        pmp.clean_up(options.mode != RepairMode::Wrap);
        std::string problem = "not wrapped";
        if (options.mode != RepairMode::Wrap) {
            pmp.remove_self_intersections();
            out = pmp.result();
            problem = detail::prepare_closed_surface(out);
            const bool changed = report.duplicate_vertices_merged + report.duplicate_faces_removed
                    + report.invalid_faces_removed + report.degenerate_faces_removed
                    + report.non_manifold_vertices_split + report.border_edges_in
                    + report.self_intersections_in + report.components_in - 1
                > 0;
            report.applied = changed ? "pmp" : "none";
            if (!problem.empty() && options.mode == RepairMode::Pmp)
                throw InputError("surface",
                    "after PMP repair: " + problem + " ("
                        + std::to_string(report.self_intersections_out)
                        + " self-intersecting face pairs, " + std::to_string(report.holes_unfilled)
                        + " holes unfilled); repair \"wrap\" or \"auto\" would wrap it");
        }
        if (!problem.empty()) {
            report.wrap_alpha = wrap_alpha(options, cell_size);
            report.wrap_offset = wrap_offset(options, cell_size);
            if (!(report.wrap_alpha > 0 && report.wrap_offset > 0))
                throw InputError("wrap", "alpha and offset must be > 0");
            out = detail::alpha_wrap(pmp.to_wrap(), report.wrap_alpha, report.wrap_offset);
            if (std::string wrap_problem = detail::prepare_closed_surface(out);
                !wrap_problem.empty())
                throw MeshError(-1, -1, "Alpha_wrap_3 produced a surface that is " + wrap_problem);
            report.wrapped = true;
            report.applied = options.mode == RepairMode::Wrap ? "wrap" : "pmp+wrap";
        }
    }
    report.vertices_out = Index(out.positions.size());
    report.faces_out = Index(out.triangles.size());
    report.volume_out = enclosed_volume(out);
    report.volume_change = report.volume_in > 0 ? report.volume_out / report.volume_in - 1 : 0;
    {
        CgalMesh sm = to_cgal(out);
        auto component = sm.add_property_map<FaceIndex, std::size_t>("f:repair_cc", 0).first;
        report.components_out = Index(PMP::connected_components(sm, component));
    }
    report.time_ms
        = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
    if (report_out)
        *report_out = report;
    return out;
}

} // namespace polycut::meshing
