// The mesh a scene's geometry names: box grids, random-plane polyhedra, CGAL meshing of implicit
// shapes and surface files (with their repair report and tet quality), volume mesh files, and
// single convex cells.
#include "polycut/sim/build_mesh.hpp"

#include "octree_part.hpp"
#include "polycut/common/error.hpp"
#include "polycut/cut/random_planes.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/io.hpp"
#include "polycut/mesh/reorder.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/convex_hull.hpp"
#include "polycut/meshing/hex_slice.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/quality.hpp"
#include "polycut/meshing/surface_file.hpp"
#include "polycut/sim/simulation.hpp"

#include <chrono>
#include <filesystem>
#include <string_view>

namespace polycut::sim {
namespace {
std::string resolve(const scene::Scene& s, const std::string& path) {
    const std::filesystem::path p(path);
    if (p.is_absolute() || s.directory.empty())
        return p.string();
    return (std::filesystem::path(s.directory) / p).string();
}

void scale_mesh(mesh::Mesh& m, double scale) {
    if (scale != 1.0)
        for (Vec3& X : m.rest)
            X *= scale;
}

/// A meshing InputError as a SceneError at the geometry key it is about ("options.cell_size" ->
/// "/geometry/cell_size", "shape.radii" -> "/geometry/radii"); any other (the surface itself
/// cannot be repaired) points at `fallback` with `subject` (the file) leading the problem.
SceneError geometry_error(
    const InputError& e, const std::string& fallback, const std::string& subject) {
    std::string_view key = e.where();
    for (std::string_view prefix : { "options.", "shape." })
        if (key.starts_with(prefix))
            key.remove_prefix(prefix.size());
    for (std::string_view k :
        { "cell_size", "sliver_bound", "optimize", "scale", "wrap", "radii", "length", "center" })
        if (key == k)
            return SceneError("/geometry/" + std::string(key), e.problem());
    return SceneError(fallback, subject + ": " + e.problem());
}

/// Mesh_3 options of an implicit or surface_file geometry. The scene parser has checked the
/// names; select_optimizers() rejects any other.
meshing::MeshingOptions meshing_options(const scene::Geometry& g) {
    meshing::MeshingOptions o;
    o.cell_size = g.cell_size;
    o.seed = g.seed;
    o.sliver_bound = g.sliver_bound;
    try {
        meshing::select_optimizers(o, g.optimize);
    } catch (const InputError& e) {
        throw SceneError("/geometry/optimize", e.problem());
    }
    return o;
}

void copy_quality(const meshing::TetQuality& q, MeshingSummary& out) {
    out.tets = q.tets;
    out.min_dihedral_deg = q.min_dihedral_deg;
    out.max_dihedral_deg = q.max_dihedral_deg;
    out.radius_ratio_min = q.radius_ratio_min;
    out.radius_ratio_p1 = q.radius_ratio_p1;
    out.radius_ratio_p50 = q.radius_ratio_p50;
    out.slivers = q.slivers;
    out.sliver_dihedral_deg = meshing::kSliverDihedralDeg;
    out.has_slivers = q.has_slivers();
    out.quality_summary = meshing::to_string(q);
}

void copy_repair(const meshing::RepairReport& r, MeshingSummary& out) {
    out.has_repair = true;
    out.repair_mode = std::string(meshing::to_string(r.mode));
    out.repair_applied = r.applied;
    out.repair_summary = r.summary();
    out.faces_in = r.faces_in;
    out.faces_out = r.faces_out;
    out.holes_filled = r.holes_filled;
    out.holes_unfilled = r.holes_unfilled;
    out.self_intersections_in = r.self_intersections_in;
    out.self_intersections_out = r.self_intersections_out;
    out.components_in = r.components_in;
    out.components_out = r.components_out;
    out.wrapped = r.wrapped;
    out.volume_in = r.volume_in;
    out.volume_out = r.volume_out;
    out.volume_change = r.volume_change;
    out.repair_ms = r.time_ms;
}

meshing::RepairMode repair_mode(scene::Repair r) {
    switch (r) {
    case scene::Repair::None:
        return meshing::RepairMode::None;
    case scene::Repair::Pmp:
        return meshing::RepairMode::Pmp;
    case scene::Repair::Wrap:
        return meshing::RepairMode::Wrap;
    case scene::Repair::Auto:
        break;
    }
    return meshing::RepairMode::Auto;
}

meshing::ComponentsMode components_mode(scene::Components c) {
    switch (c) {
    case scene::Components::Largest:
        return meshing::ComponentsMode::Largest;
    case scene::Components::Refuse:
        return meshing::ComponentsMode::Refuse;
    case scene::Components::Union:
        break;
    }
    return meshing::ComponentsMode::Union;
}

/// CGAL Mesh_3 of an implicit shape, with progress on stderr.
mesh::Mesh implicit_mesh(const scene::Geometry& g, MeshingSummary& summary) {
    const meshing::ImplicitShape shape = implicit_shape(g);
    const meshing::MeshingOptions options = meshing_options(g);
    const auto start = std::chrono::steady_clock::now();
    mesh::Mesh m;
    try {
        m = meshing::mesh_implicit(shape, options, meshing::print_progress);
    } catch (const InputError& e) {
        throw geometry_error(
            e, "/geometry", "shape \"" + std::string(scene::to_string(g.shape)) + "\"");
    }
    summary.mesh_ms
        = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
    copy_quality(meshing::tet_quality(m), summary);
    summary.total_ms = summary.mesh_ms;
    summary.source = "implicit";
    summary.meshed = true;
    return m;
}

/// A surface file read, repaired as the scene says, and meshed by CGAL Mesh_3 (in metres).
mesh::Mesh surface_file_mesh(const scene::Scene& s, MeshingSummary& summary) {
    const scene::Geometry& g = s.geometry;
    meshing::SurfaceFileOptions o;
    o.scale = g.scale;
    o.meshing = meshing_options(g);
    o.repair.mode = repair_mode(g.repair);
    o.repair.components = components_mode(g.components);
    o.repair.wrap_alpha = g.wrap_alpha;
    o.repair.wrap_offset = g.wrap_offset;
    const std::string path = resolve(s, g.path);
    meshing::SurfaceFileMesh r;
    try {
        r = meshing::mesh_surface_file(path, o); // FileError passes through
    } catch (const InputError& e) {
        throw geometry_error(e, "/geometry/path", path);
    }
    copy_repair(r.repair, summary);
    copy_quality(r.quality, summary);
    summary.mesh_ms = r.mesh_ms;
    summary.total_ms = r.total_ms;
    summary.source = "surface_file";
    summary.meshed = true;
    return std::move(r.mesh);
}

/// The closed surface a hex_slice geometry slices: the file, read, scaled and repaired as the
/// scene says, or the boundary of a Mesh_3 mesh of the implicit shape (no optimisers: only its
/// surface triangles of size triangle_size are used).
meshing::SurfaceMesh hex_slice_surface(const scene::Scene& s, MeshingSummary& summary) {
    const scene::Geometry& g = s.geometry;
    if (g.path.empty()) {
        meshing::MeshingOptions o;
        o.cell_size = g.triangle_size > 0 ? g.triangle_size : g.cell_size / 3;
        o.seed = g.seed;
        o.perturb = o.exude = false;
        try {
            return meshing::boundary_surface(meshing::mesh_implicit(implicit_shape(g), o));
        } catch (const InputError& e) {
            throw geometry_error(
                e, "/geometry/surface", "shape \"" + std::string(scene::to_string(g.shape)) + "\"");
        }
    }
    const std::string path = resolve(s, g.path);
    meshing::SurfaceMesh surface = meshing::read_surface(path, false); // FileError passes
    for (Vec3& p : surface.positions)
        p *= g.scale;
    meshing::RepairOptions o;
    o.mode = repair_mode(g.repair);
    o.components = components_mode(g.components);
    o.wrap_alpha = g.wrap_alpha;
    o.wrap_offset = g.wrap_offset;
    meshing::RepairReport report;
    try {
        surface = meshing::repair_surface(surface, o, g.cell_size, &report);
    } catch (const InputError& e) {
        throw geometry_error(e, "/geometry/surface", path);
    }
    copy_repair(report, summary);
    return surface;
}

/// Hexahedral slicing (003 sec. 10) of the geometry's surface.
mesh::Mesh hex_slice_mesh(const scene::Scene& s, MeshingSummary& summary) {
    const scene::Geometry& g = s.geometry;
    const auto start = std::chrono::steady_clock::now();
    const meshing::SurfaceMesh surface = hex_slice_surface(s, summary);
    meshing::HexSliceOptions o;
    o.cell_size = g.cell_size;
    o.merge_fraction = g.merge_fraction;
    meshing::HexSliceReport report;
    mesh::Mesh m;
    try {
        m = meshing::hex_slice(surface, o, &report);
    } catch (const InputError& e) {
        throw geometry_error(e, "/geometry/surface", "hex_slice");
    }
    meshing::print_progress("hex_slice: " + report.summary());
    summary.quality_summary = "hex_slice " + report.summary();
    summary.mesh_ms = report.time_ms;
    summary.total_ms
        = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
    summary.source = "hex_slice";
    summary.meshed = true;
    return m;
}

/// One convex polyhedral cell (seed 000 Fig. 1). The hull is taken of the points as written
/// (or of the shape about the origin) and scaled / moved afterwards, so that points the file
/// puts exactly on one plane stay exactly coplanar for CGAL's exact predicates.
mesh::Mesh convex_hull_mesh(const scene::Geometry& g) {
    const bool shape = g.shape != scene::Shape::None; // truncated_octahedron
    mesh::Mesh m;
    try {
        m = meshing::convex_hull_cell(
            shape ? meshing::truncated_octahedron_points(g.edge_length) : g.points);
    } catch (const meshing::ConvexHullError& e) {
        throw SceneError(e.index() == kNone || shape
                ? std::string("/geometry/points")
                : "/geometry/points/" + std::to_string(e.index()),
            e.problem());
    } catch (const InputError& e) {
        throw SceneError(shape ? "/geometry/size" : "/geometry/points", e.problem());
    }
    if (shape)
        for (Vec3& X : m.rest)
            X += g.center;
    else
        scale_mesh(m, g.scale);
    return m;
}
/// Maps a grid on the unit cube onto the hexahedron with these corners (VTK order), trilinearly.
void map_to_corners(mesh::Mesh& m, const std::vector<Vec3>& c) {
    for (Vec3& X : m.rest) {
        const double u = X.x(), v = X.y(), w = X.z();
        const Vec3 bottom
            = (1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] + (1 - u) * v * c[3];
        const Vec3 top
            = (1 - u) * (1 - v) * c[4] + u * (1 - v) * c[5] + u * v * c[6] + (1 - u) * v * c[7];
        X = (1 - w) * bottom + w * top;
    }
}
} // namespace

mesh::Mesh build_mesh(const scene::Scene& s, MeshingSummary* summary) {
    const scene::Geometry& g = s.geometry;
    MeshingSummary meshed;
    mesh::Mesh m;
    switch (g.kind) {
    case scene::Geometry::Kind::Box:
    case scene::Geometry::Kind::RandomPlanes: {
        mesh::BoxGrid grid;
        grid.lo = g.corners.empty() ? g.origin : Vec3::Zero();
        grid.hi = g.corners.empty() ? Vec3(g.origin + g.size) : Vec3::Ones();
        grid.cells = g.cells;
        if (g.kind == scene::Geometry::Kind::RandomPlanes) {
            // 000 Fig. 2: each hex block split by random planes into convex polyhedra; one plane
            // per split, cells picked in proportion to volume, planes_per_cell splits per block on
            // average.
            const mesh::Mesh hexes = mesh::hex_grid(grid);
            m = cut::split_by_random_planes(
                hexes, g.planes_per_cell * int(hexes.num_cells()), g.seed);
        } else if (g.elements == scene::Elements::Hex)
            m = mesh::hex_grid(grid);
        else
            m = mesh::tet_grid(grid,
                g.tet_split == scene::TetSplit::Five ? mesh::TetSplit::Five
                                                     : mesh::TetSplit::Kuhn6);
        if (!g.corners.empty())
            map_to_corners(m, g.corners);
        break;
    }
    case scene::Geometry::Kind::Implicit:
        m = implicit_mesh(g, meshed);
        if (g.node_order == scene::NodeOrder::Rcm)
            mesh::reorder_for_locality(m); // Mesh_3 numbers nodes in insertion order (issue 18)
        break;
    case scene::Geometry::Kind::SurfaceFile:
        m = surface_file_mesh(s, meshed);
        if (g.node_order == scene::NodeOrder::Rcm)
            mesh::reorder_for_locality(m);
        break;
    case scene::Geometry::Kind::MeshFile:
        m = mesh::read_volume_mesh(resolve(s, g.path));
        scale_mesh(m, g.scale);
        break;
    case scene::Geometry::Kind::ConvexHull:
        m = convex_hull_mesh(g);
        break;
    case scene::Geometry::Kind::HexSlice:
        m = hex_slice_mesh(s, meshed);
        mesh::reorder_for_locality(m);
        break;
    case scene::Geometry::Kind::Octree:
        m = make_octree(s)->build_mesh();
        break;
    }
    if (m.num_cells() == 0)
        throw SceneError("/geometry", "the geometry produced no cells");
    mesh::ValidationOptions checks;
    if (g.kind == scene::Geometry::Kind::RandomPlanes)
        checks.planarity_tol = 2e-2; // plane splits snap nodes within the cutter's tolerance
    mesh::validate(m, checks);
    if ((s.method == scene::Method::Tet)
        && std::any_of(m.cells.begin(), m.cells.end(),
            [](const mesh::Cell& c) { return c.shape != mesh::CellShape::Tet; }))
        throw SceneError("/method",
            "\"tet\" needs a pure tetrahedral mesh; this geometry has other "
            "cells (use \"mvc\" or \"harmonic\")");
    if (s.method == scene::Method::Mvc && g.kind == scene::Geometry::Kind::HexSlice) {
        // Mean value coordinates are built for convex cells (000 sec. 3); on the non-convex
        // pieces of a sliced surface the steps explode (measured: 15 of 20 rolled back).
        Index nonconvex = 0;
        for (Index c = 0; c < m.num_cells(); ++c)
            nonconvex += !geometry::polyhedron_is_convex(m.rest, m.cell_face_loops(c));
        if (nonconvex > 0)
            throw SceneError("/method",
                "\"mvc\" needs convex cells; hex_slice made " + std::to_string(nonconvex)
                    + " non-convex cells (use \"dg\" or \"harmonic\")");
    }
    if (summary)
        *summary = std::move(meshed);
    return m;
}

} // namespace polycut::sim
