// Repair of triangle surfaces that cannot bound a volume as they are (scanned and segmented
// organs: duplicate vertices and faces, degenerate triangles, cracks, small holes, folds), with
// CGAL Polygon_mesh_processing, or replacement by a watertight wrap (CGAL Alpha_wrap_3); and the
// choice of which connected components to keep. CGAL stays in the .cpp files.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/meshing/surface.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace polycut::meshing {

/// What to do with a surface that is not a closed, self-intersection-free 2-manifold.
enum class RepairMode {
    /// Nothing if the surface is clean; otherwise Pmp, and if that leaves it open or
    /// self-intersecting, Wrap. The default.
    Auto,
    /// No change: a surface that is not clean is an error.
    None,
    /// Polygon_mesh_processing only: merge duplicate vertices and faces, drop invalid and
    /// degenerate faces, orient, stitch cracks, fill holes (refined and faired), remove local
    /// self-intersections (CGAL 5.5 experimental). An error if the result is still not clean.
    Pmp,
    /// Alpha_wrap_3 of the (soup-cleaned) triangles: always closed and free of
    /// self-intersections; smooths details smaller than alpha and grows the volume by ~offset
    /// times the area.
    Wrap,
};

/// Which connected components of the surface are meshed. Components are counted after
/// stitching and hole filling; a closed shell nested in another (a cavity) is a component too.
enum class ComponentsMode {
    Union, ///< all of them, as one volume (the default); the wrap merges overlapping ones
    Largest, ///< only the one enclosing the largest volume
    Refuse, ///< more than one is an error naming the count and volumes
};

/// Repair options. Lengths in the surface's units (metres for scenes).
struct RepairOptions {
    RepairMode mode = RepairMode::Auto;
    ComponentsMode components = ComponentsMode::Union;
    /// Alpha_wrap_3 alpha [m]: the radius of the ball that carves the wrap; cavities and
    /// tunnels narrower than ~alpha are closed over. <= 0: the meshing cell size.
    double wrap_alpha = 0;
    /// Alpha_wrap_3 offset [m]: distance of the wrap from the input. <= 0: the meshing cell
    /// size / 30 (below Mesh_3's default facet distance, cell size / 10).
    double wrap_offset = 0;
    /// Holes with more border edges than this are not filled (a scan that misses a whole side
    /// is left to the wrap).
    Index max_hole_edges = 1000;
};

/// What repair_surface() found and did. Counts refer to the triangles after fan triangulation.
struct RepairReport {
    RepairMode mode = RepairMode::Auto; ///< what was asked
    /// What was done: "none" (the surface was clean), "pmp", "wrap" or "pmp+wrap" (auto:
    /// PMP could not make it clean).
    std::string applied = "none";
    Index vertices_in = 0, faces_in = 0; ///< input size
    Index vertices_out = 0, faces_out = 0; ///< output size
    Index duplicate_vertices_merged = 0; ///< vertices with the coordinates of an earlier one
    Index duplicate_faces_removed = 0; ///< faces on the vertices of another (either orientation)
    Index invalid_faces_removed = 0; ///< faces left with < 3 distinct vertices after merging
    Index degenerate_faces_removed = 0; ///< zero-area faces collapsed (needles and caps)
    Index non_manifold_vertices_split = 0; ///< vertices duplicated to orient the soup
    Index border_edges_in = 0; ///< border edges after merging and stitching
    Index holes_filled = 0; ///< boundary cycles closed by new triangles
    Index holes_unfilled = 0; ///< boundary cycles left open (too large or filling failed)
    Index self_intersections_in = 0; ///< intersecting face pairs after hole filling
    Index self_intersections_out = 0; ///< ... after PMP's local removal (0 if it succeeded)
    Index components_in = 0; ///< connected components before the components option
    Index components_out = 0; ///< components of the output
    bool wrapped = false; ///< the output is an Alpha_wrap_3 wrap
    double wrap_alpha = 0, wrap_offset = 0; ///< alpha and offset used [m] (0 if not wrapped)
    /// Volumes [m^3]: in, the enclosed volume of the input after orientation (for an input that
    /// is not closed, about the centre of its bounding box: an estimate); out, of the output.
    double volume_in = 0, volume_out = 0;
    double volume_change = 0; ///< volume_out / volume_in - 1
    double time_ms = 0; ///< wall time of repair_surface() [ms]

    /// One line for logs, e.g. "pmp: 1254 -> 1260 faces, 10 duplicate vertices, 2 duplicate
    /// faces, 3 degenerate, 1 hole filled, 12 self-intersections removed, volume 1.345e-04 ->
    /// 1.344e-04 m^3 (-0.05 %), 18 ms".
    std::string summary() const;
};

/// Repairs (or wraps) `surface` so that it bounds a volume, as `options` say, and returns the
/// result: a closed, outward-oriented, self-intersection-free triangle 2-manifold with only the
/// components asked for. `cell_size` [m] sets the default wrap alpha and offset. Fills `report`
/// if given. Throws InputError (where "surface") when the input has non-finite coordinates or
/// ids out of range, when mode None or Pmp cannot produce a clean surface (the message says
/// what is left and suggests "wrap"), or when components is Refuse and there are several.
SurfaceMesh repair_surface(const SurfaceMesh& surface, const RepairOptions& options,
    double cell_size, RepairReport* report = nullptr);

/// The scene spelling of a mode: "auto", "none", "pmp", "wrap".
std::string_view to_string(RepairMode mode);
/// "union", "largest", "refuse".
std::string_view to_string(ComponentsMode mode);
/// Parses the scene spelling; nullopt if unknown.
std::optional<RepairMode> parse_repair_mode(std::string_view text);
std::optional<ComponentsMode> parse_components_mode(std::string_view text);

} // namespace polycut::meshing
