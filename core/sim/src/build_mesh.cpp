// The mesh a scene's geometry names: box grids, random-plane polyhedra, CGAL meshing of implicit
// shapes and surface files, volume mesh files, and single convex cells.
#include "polycut/sim/build_mesh.hpp"

#include "polycut/common/error.hpp"
#include "polycut/cut/random_planes.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/io.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/convex_hull.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/surface.hpp"

#include <filesystem>

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

/// One convex polyhedral cell (seed 000 Fig. 1). The hull is taken of the points as written
/// (or of the shape about the origin) and scaled / moved afterwards, so that points the file
/// puts exactly on one plane stay exactly coplanar for CGAL's exact predicates.
mesh::Mesh convex_hull_mesh(const scene::Geometry& g) {
    const bool shape = !g.shape.empty(); // "truncated_octahedron"
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
} // namespace

mesh::Mesh build_mesh(const scene::Scene& s) {
    const scene::Geometry& g = s.geometry;
    mesh::Mesh m;
    switch (g.kind) {
    case scene::Geometry::Kind::Box:
    case scene::Geometry::Kind::RandomPlanes: {
        mesh::BoxGrid grid;
        grid.lo = g.origin;
        grid.hi = g.origin + g.size;
        grid.cells = g.cells;
        if (g.kind == scene::Geometry::Kind::RandomPlanes) {
            // 000 Fig. 2: each hex block split by random planes into convex polyhedra; one plane
            // per split, cells picked in proportion to volume, planes_per_cell splits per block on
            // average.
            const mesh::Mesh hexes = mesh::hex_grid(grid);
            m = cut::split_by_random_planes(
                hexes, g.planes_per_cell * int(hexes.num_cells()), g.seed);
        } else if (g.elements == "hex")
            m = mesh::hex_grid(grid);
        else
            m = mesh::tet_grid(
                grid, g.tet_split == "five" ? mesh::TetSplit::Five : mesh::TetSplit::Kuhn6);
        break;
    }
    case scene::Geometry::Kind::Implicit: {
        meshing::ImplicitShape shape;
        if (g.shape == "sphere")
            shape = meshing::ImplicitShape::sphere(g.radii.x(), g.center);
        else if (g.shape == "ellipsoid")
            shape = meshing::ImplicitShape::ellipsoid(g.radii, g.center);
        else if (g.shape == "capsule")
            shape = meshing::ImplicitShape::capsule(g.radii.x(), g.length, Vec3::UnitZ(), g.center);
        else
            shape = meshing::ImplicitShape::blob(g.radii, g.center);
        meshing::MeshingOptions opt;
        opt.cell_size = g.cell_size;
        opt.seed = g.seed;
        try {
            m = meshing::mesh_implicit(shape, opt);
        } catch (const InputError& e) {
            throw SceneError("/geometry", e.what());
        }
        break;
    }
    case scene::Geometry::Kind::SurfaceFile: {
        meshing::MeshingOptions opt;
        opt.cell_size = g.cell_size / g.scale; // mesh in file units, then scale
        opt.seed = g.seed;
        try {
            m = meshing::mesh_surface_file(resolve(s, g.path), opt);
        } catch (const InputError& e) {
            throw SceneError("/geometry/path", e.what());
        }
        scale_mesh(m, g.scale);
        break;
    }
    case scene::Geometry::Kind::MeshFile:
        m = mesh::read_volume_mesh(resolve(s, g.path));
        scale_mesh(m, g.scale);
        break;
    case scene::Geometry::Kind::ConvexHull:
        m = convex_hull_mesh(g);
        break;
    }
    if (m.num_cells() == 0)
        throw SceneError("/geometry", "the geometry produced no cells");
    mesh::ValidationOptions checks;
    if (g.kind == scene::Geometry::Kind::RandomPlanes)
        checks.planarity_tol = 2e-2; // plane splits snap nodes within the cutter's tolerance
    mesh::validate(m, checks);
    if ((s.method == "tet") && std::any_of(m.cells.begin(), m.cells.end(), [](const mesh::Cell& c) {
            return c.shape != mesh::CellShape::Tet;
        }))
        throw SceneError("/method",
            "\"tet\" needs a pure tetrahedral mesh; this geometry has other "
            "cells (use \"mvc\" or \"harmonic\")");
    return m;
}

} // namespace polycut::sim
