// The surface-file pipeline: read, scale, repair, Mesh_3, quality, with one progress line per
// phase (no CGAL here: the phases live in io.cpp, repair.cpp, wrap.cpp and surface.cpp).
#include "polycut/meshing/surface_file.hpp"

#include "polycut/common/error.hpp"
#include "polycut/meshing/surface.hpp"
#include "surface_prepare.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace polycut::meshing {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

} // namespace

SurfaceFileMesh mesh_surface_file(const std::string& path, const SurfaceFileOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check_options(options.meshing);
    if (!(std::isfinite(options.scale) && options.scale > 0))
        throw InputError("scale", "must be finite and > 0");
    auto say = [&](const std::string& line) {
        if (options.progress)
            options.progress(line);
    };
    const std::string name = std::filesystem::path(path).filename().string();

    SurfaceFileMesh out;
    SurfaceMesh surface = read_surface(path, false);
    if (options.scale != 1)
        for (Vec3& p : surface.positions)
            p *= options.scale;
    out.read_ms = ms_since(start);
    say("read " + name + ": " + std::to_string(surface.positions.size()) + " vertices, "
        + std::to_string(surface.triangles.size()) + " triangles, "
        + std::to_string(long(out.read_ms)) + " ms");

    const SurfaceMesh closed
        = repair_surface(surface, options.repair, options.meshing.cell_size, &out.repair);
    say("repair: " + out.repair.summary());

    const auto mesh_start = std::chrono::steady_clock::now();
    out.mesh = detail::mesh_prepared_surface(closed, options.meshing, say);
    out.mesh_ms = ms_since(mesh_start);
    out.quality = tet_quality(out.mesh);
    say("quality: " + to_string(out.quality));
    out.total_ms = ms_since(start);
    say("done: " + std::to_string(out.mesh.num_nodes()) + " nodes, "
        + std::to_string(out.mesh.num_cells()) + " tets, " + std::to_string(long(out.total_ms))
        + " ms");
    return out;
}

mesh::Mesh mesh_surface_file(const std::string& path, const MeshingOptions& options) {
    SurfaceFileOptions o;
    o.meshing = options;
    return mesh_surface_file(path, o).mesh;
}

} // namespace polycut::meshing
