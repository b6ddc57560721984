// Mesh generation by hexahedral slicing (003 sec. 10): a grid of cubes intersected with a closed
// triangle surface. Cubes inside the surface stay hexahedra; cubes the surface crosses become
// the exact intersection polyhedra (possibly non-convex, possibly several per cube); pieces
// below a volume fraction of a cube are merged into a neighbour (sliver merging). The cells
// fill exactly the volume the surface encloses, so the strain energy is integrated over the
// exact volume.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/surface.hpp"

#include <array>
#include <string>

namespace polycut::meshing {

/// Options of hex_slice().
struct HexSliceOptions {
    /// Edge length h of the grid's cubes [m], > 0.
    double cell_size = 0.01;
    /// Sliver merging (003 sec. 10): a piece of a cut cube whose volume is below
    /// merge_fraction * h^3 is merged into the neighbouring piece it shares the largest grid
    /// face with, until every merged group reaches that volume [dimensionless, in [0, 1)].
    /// 0 keeps every piece.
    double merge_fraction = 0.1;
};

/// What hex_slice() built.
struct HexSliceReport {
    std::array<Index, 3> grid { 0, 0, 0 }; ///< cubes of the grid along x, y, z
    Index hexes = 0; ///< cells that are whole cubes inside the surface (CellShape::Hex)
    Index cut_cells = 0; ///< cells made of cut cubes' pieces (after merging)
    Index pieces = 0; ///< connected pieces of the cut cubes before merging
    Index merged = 0; ///< pieces merged into a neighbour because they were small
    /// grid faces whose inside part has a hole (a polygon face cannot have one): the pieces on
    /// both sides are merged into one cell
    Index holed_faces = 0;
    Index small_kept = 0; ///< small pieces with no neighbour to merge into (kept as cells)
    Index grid_shifts = 0; ///< times the grid was moved because a surface vertex lay on it
    Index surface_triangles = 0; ///< triangles of the input surface
    Index sliced_triangles = 0; ///< triangles after refining the surface along the grid planes
    double surface_volume = 0; ///< volume the surface encloses [m^3]
    double mesh_volume = 0; ///< sum of the cells' rest volumes [m^3]
    double min_cell_volume = 0; ///< smallest cell volume [m^3]
    double time_ms = 0; ///< wall time of hex_slice() [ms]
    /// One line for logs, e.g. "hex_slice h = 0.012 m: 9x6x5 cubes, 41 hexes + 96 cut cells
    /// (203 pieces, 12 merged, 0 holed faces), volume 1.2e-4 m^3 (surface 1.2e-4, rel. diff
    /// 3e-16), 85 ms".
    std::string summary() const;
};

/// The hex-sliced mesh of the volume a closed surface bounds [m]. The surface is checked and
/// oriented as for Mesh_3 (closed, orientable, no self-intersections); it is refined along the
/// grid planes with CGAL's corefinement in exact arithmetic, so the pieces of neighbouring cubes
/// share their nodes exactly and the cells' volumes add up to the surface's enclosed volume to
/// round-off. Cut cells have the surface's triangles (clipped to the cube) as skin faces and
/// planar polygons on the grid planes as interior faces. The grid is placed around the
/// surface's bounding box and moved by a small fraction of h if a surface vertex lies exactly
/// on a grid plane. Throws InputError ("surface": not closed, ...; "options.<field>": out of
/// range), MeshError if no cell results. Method mvc needs convex cells, which cut cells
/// mostly are not: use dg or harmonic on hex-sliced meshes.
mesh::Mesh hex_slice(
    const SurfaceMesh& surface, const HexSliceOptions& options, HexSliceReport* report = nullptr);

} // namespace polycut::meshing
