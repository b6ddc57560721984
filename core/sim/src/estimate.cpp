// Scene size and memory estimate before building (estimate.hpp).
#include "polycut/sim/estimate.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

namespace polycut::sim {

namespace {
/// Volume of a regular tetrahedron of edge h over h^3 (Mesh_3 aims at cells of size h).
constexpr double kRegularTet = 0.1178511;
/// Memory per cell: this many times the bytes of its (3n)^2 element matrix, plus a constant.
constexpr double kMatrixFactor = 4.5;
constexpr double kCellOverhead = 1024.0;
/// The process before any scene (libraries, sockets, buffers) [bytes]; not counted.
} // namespace

SceneEstimate estimate(const scene::Scene& s) {
    using Kind = scene::Geometry::Kind;
    const scene::Geometry& g = s.geometry;
    SceneEstimate e;
    const double blocks = double(std::max(g.cells.x(), 0)) * double(std::max(g.cells.y(), 0))
        * double(std::max(g.cells.z(), 0));
    switch (g.kind) {
    case Kind::Box:
        if (g.elements == scene::Elements::Hex) {
            e.cells = blocks;
            e.nodes_per_cell = 8;
        } else {
            e.cells = blocks * (g.tet_split == scene::TetSplit::Five ? 5.0 : 6.0);
        }
        e.basis = "box of " + std::to_string(long(blocks)) + " blocks";
        break;
    case Kind::RandomPlanes:
        // Each plane splits a block's pieces: at most (planes + 1)^2 pieces of ~10 nodes.
        e.cells = blocks * std::pow(double(g.planes_per_cell) + 1.0, 2.0);
        e.nodes_per_cell = 10;
        e.basis = "random planes in " + std::to_string(long(blocks)) + " blocks";
        break;
    case Kind::HexSlice:
        if (!g.path.empty()) {
            e.known = false; // a surface file's volume is known only after reading it
            e.basis = "hex-sliced surface file (not estimated)";
            return e;
        }
        [[fallthrough]];
    case Kind::Implicit: {
        const double pi = std::numbers::pi;
        const Vec3 r = g.radii;
        double volume = 4.0 / 3.0 * pi * r.x() * r.y() * r.z();
        if (g.shape == scene::Shape::Sphere) {
            volume = 4.0 / 3.0 * pi * std::pow(r.x(), 3);
        } else if (g.shape == scene::Shape::Capsule) {
            volume = pi * r.x() * r.x() * g.length + 4.0 / 3.0 * pi * std::pow(r.x(), 3);
        } else if (g.shape == scene::Shape::Blob) {
            volume *= 2.0; // lobes reach past the radii
        }
        const double h = std::max(g.cell_size, 1e-12);
        if (g.kind == Kind::HexSlice) {
            // About one cell per cube of h^3, the cut ones with ~20 nodes.
            e.cells = 1.5 * volume / (h * h * h) + 1;
            e.nodes_per_cell = 20;
            e.basis = std::string(scene::to_string(g.shape)) + " hex-sliced at cell size "
                + std::to_string(h) + " m";
            break;
        }
        e.cells = 2.0 * volume / (kRegularTet * h * h * h); // Mesh_3 cells run smaller than h
        e.basis = std::string(scene::to_string(g.shape)) + " meshed at cell size "
            + std::to_string(h) + " m";
        break;
    }
    case Kind::MeshFile:
    case Kind::SurfaceFile: {
        std::error_code ec;
        const auto size = std::filesystem::file_size(g.path, ec);
        if (ec || g.kind == Kind::SurfaceFile) {
            // A surface's volume (and so its tet count) is known only after reading it; the
            // scene directory is the operator's, so these are not refused by the estimate.
            e.known = false;
            e.basis = "surface or mesh file (not estimated)";
            return e;
        }
        e.cells = double(size) / 20.0; // a cell line takes at least ~20 bytes of text
        e.basis = "mesh file of " + std::to_string(size) + " bytes";
        break;
    }
    case Kind::Octree: {
        // base cells over the object's box, plus a skin of surface cells (area / size^2, twice
        // for the 2:1 transition layers); regions are not counted
        const Vec3 box = g.octree.object == scene::OctreeObject::Box ? g.size : Vec3(2.0 * g.radii);
        const double c = std::max(g.cell_size, 1e-12);
        const double sc = g.octree.surface_cell_size > 0 ? g.octree.surface_cell_size : c;
        const double area = 2.0 * (box.x() * box.y() + box.y() * box.z() + box.z() * box.x());
        e.cells = box.prod() / (c * c * c)
            + (g.octree.object == scene::OctreeObject::Box ? 0.0 : 2.0 * area / (sc * sc));
        e.nodes_per_cell = 12;
        e.known = g.octree.object != scene::OctreeObject::SurfaceFile;
        e.basis = "octree of " + std::to_string(c) + " m cells";
        break;
    }
    case Kind::ConvexHull:
        e.cells = 1;
        e.nodes_per_cell = std::max<double>(double(g.points.size()), 24.0);
        e.basis = "one convex cell";
        break;
    }
    const double matrix = 8.0 * std::pow(3.0 * e.nodes_per_cell, 2.0);
    e.bytes = e.cells * (kMatrixFactor * matrix + kCellOverhead);
    return e;
}

std::optional<std::string> over_budget(const scene::Scene& scene, std::uint64_t budget) {
    if (budget == 0) {
        return std::nullopt;
    }
    const SceneEstimate e = estimate(scene);
    if (!e.known || e.bytes <= double(budget)) {
        return std::nullopt;
    }
    char text[256];
    std::snprintf(text, sizeof text,
        "scene too large: ~%.3g cells (%s) need ~%.0f MB, above the server's budget of %.0f MB "
        "(polycut-server --scene-memory)",
        e.cells, e.basis.c_str(), e.bytes / 1e6, double(budget) / 1e6);
    return std::string(text);
}

} // namespace polycut::sim
