// Closed triangle surfaces: reading and writing OFF/OBJ/STL files (through CGAL's IO), checks for
// meshing (closed, 2-manifold, not self-intersecting), the boundary of a volume mesh as a surface,
// and tetrahedral meshing of the enclosed volume with CGAL Mesh_3.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"

#include <array>
#include <string>
#include <vector>

namespace polycut::meshing {

/// A triangle surface.
struct SurfaceMesh {
    std::vector<Vec3> positions; ///< vertex positions (#V) [m]
    std::vector<std::array<Index, 3>> triangles; ///< vertex ids (#T x 3), outward (right hand)
};

/// Reads an OFF, OBJ or STL file (by extension, case-insensitive). Polygons with more than three
/// vertices are triangulated; duplicate STL vertices are merged. With require_closed, the surface
/// must also be a closed, orientable 2-manifold without self-intersections (what meshing needs);
/// it is then oriented outward. Throws FileError(path, 0, problem) for a missing or unreadable
/// file, an unsupported extension, unparsable content, no triangles, a vertex id out of range, a
/// degenerate polygon, a non-finite coordinate, or (with require_closed) an open, non-manifold or
/// self-intersecting surface. CGAL's readers report no line numbers, hence line 0.
SurfaceMesh read_surface(const std::string& path, bool require_closed = true);

/// Writes the surface as OFF, OBJ or STL (by extension) with 17 significant digits. Throws
/// FileError if the file cannot be written or the extension is not supported.
void write_surface(const std::string& path, const SurfaceMesh& surface);

/// Why the surface cannot bound a volume ("3 border edges", "self-intersecting", ...), or an
/// empty string if it is a closed, orientable, self-intersection-free triangle 2-manifold with
/// finite coordinates and valid ids.
std::string closed_surface_problem(const SurfaceMesh& surface);

/// Enclosed volume of a closed, outward-oriented surface [m^3] (divergence theorem).
double enclosed_volume(const SurfaceMesh& surface);

/// Boundary faces (skin and cut) of a volume mesh, fanned into triangles, with the nodes they use
/// renumbered compactly in increasing node order. Orientation is outward.
SurfaceMesh boundary_surface(const mesh::Mesh& mesh);

/// Tetrahedral mesh of the volume a closed surface bounds (CGAL Mesh_3, polyhedral domain with
/// sharp features detected at options.feature_angle). Orients the surface outward first. Throws
/// InputError if closed_surface_problem() is not empty or the options are invalid, MeshError if
/// CGAL produced no cell.
mesh::Mesh mesh_surface(const SurfaceMesh& surface, const MeshingOptions& options);

/// read_surface(path) then mesh_surface().
mesh::Mesh mesh_surface_file(const std::string& path, const MeshingOptions& options);

} // namespace polycut::meshing
