// A surface file to a tet mesh in one call, with everything the runner reports: read, scale,
// repair or wrap (repair.hpp), CGAL Mesh_3 with its optimisers, and the tets' quality; one
// progress line per phase.
#pragma once

#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"
#include "polycut/meshing/quality.hpp"
#include "polycut/meshing/repair.hpp"

#include <functional>
#include <string>

namespace polycut::meshing {

/// Options of mesh_surface_file(). Lengths in metres (after `scale`).
struct SurfaceFileOptions {
    double scale = 1; ///< file units to metres, applied to the positions on reading (> 0)
    MeshingOptions meshing; ///< Mesh_3 sizes [m], optimisers and seed
    RepairOptions repair; ///< repair / wrap and components [m]
    ProgressSink progress = print_progress; ///< empty: silent
};

/// What mesh_surface_file() produced and measured.
struct SurfaceFileMesh {
    mesh::Mesh mesh; ///< positions [m]
    RepairReport repair;
    TetQuality quality;
    double read_ms = 0; ///< reading and checking the file [ms]
    double mesh_ms = 0; ///< Mesh_3 with its optimisers [ms]
    double total_ms = 0; ///< the whole call [ms]
};

/// Reads the surface file (read_surface(path, false)), scales it, repairs it as
/// options.repair says, meshes the volume with CGAL Mesh_3 and measures the tets. Throws
/// FileError for an unreadable file (with line or byte offset), InputError for bad options or
/// a surface the repair mode cannot fix, MeshError if Mesh_3 produced no tets.
SurfaceFileMesh mesh_surface_file(const std::string& path, const SurfaceFileOptions& options);

} // namespace polycut::meshing
