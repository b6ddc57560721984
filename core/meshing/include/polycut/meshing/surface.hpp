// Closed triangle surfaces: reading and writing OFF/OBJ/STL/PLY files (through CGAL's IO), checks
// for meshing (closed, 2-manifold, not self-intersecting), the boundary of a volume mesh as a
// surface, and tetrahedral meshing of the enclosed volume with CGAL Mesh_3.
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

/// Reads a surface file, by extension (case-insensitive): .off (ASCII, or binary "OFF BINARY"),
/// .obj, .stl (ASCII or binary), .ply (ASCII or binary, either byte order). Polygons with more
/// than three vertices are fanned into triangles; repeated STL corners are merged. The whole
/// file is scanned before CGAL parses it: counts are bounded by the bytes that follow, every
/// coordinate must be finite and every id in range. With require_closed, the surface must also
/// be a closed, orientable 2-manifold without self-intersections or degenerate triangles (what
/// meshing needs as it is; see repair_surface() otherwise); it is then oriented outward.
/// Throws FileError(path, line, problem) for a missing, empty or unreadable file, an
/// unsupported extension, malformed content (line of a text file; "byte N: " leads the
/// problem for binary files), no faces, an id out of range, a polygon of < 3 vertices, a
/// non-finite coordinate, or (with require_closed) a surface that is not closed.
SurfaceMesh read_surface(const std::string& path, bool require_closed = true);

/// How write_surface() encodes a file.
enum class SurfaceEncoding {
    Ascii, ///< 17 significant digits: positions round-trip exactly
    Binary, ///< OFF BINARY, binary STL, binary little-endian PLY: float32 positions (STL, OFF)
};

/// Writes the surface as OFF, OBJ, STL or PLY (by extension). Throws FileError if the file
/// cannot be written, the extension is not supported, or Binary is asked for OBJ.
void write_surface(const std::string& path, const SurfaceMesh& surface,
    SurfaceEncoding encoding = SurfaceEncoding::Ascii);

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

/// The tet mesh of a surface file with the default repair (RepairMode::Auto, all components)
/// and progress on stderr: mesh_surface_file(path, SurfaceFileOptions) of surface_file.hpp,
/// which also returns the repair report and the tets' quality.
mesh::Mesh mesh_surface_file(const std::string& path, const MeshingOptions& options);

} // namespace polycut::meshing
