// A single polyhedral cell in local numbering (node positions + outward face loops), independent
// of the Mesh, and an orientation-independent fan triangulation of its faces (the harmonic basis
// uses it for inside tests and its integration tetrahedra; mean value cells triangulate faces by
// Delaunay instead, mean_value_triangulation(), because their basis depends on it: 000 sec. 3.2).
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <vector>

namespace polycut::basis {

/// A cell in local numbering.
struct CellGeometry {
    std::vector<Vec3> nodes; ///< node positions (#n) [m], the cell's `nodes` order
    std::vector<std::vector<Index>> loops; ///< outward face loops of local node indices
};

/// Cell `cell` of `mesh` in local numbering: nodes in Cell::nodes order, loops outward.
/// Throws MeshError if a face uses a node that is not one of the cell's nodes.
CellGeometry cell_geometry(const mesh::Mesh& mesh, Index cell);

/// A surface triangle of a cell: local node indices (outward) and the face it lies in.
struct SurfaceTriangle {
    std::array<Index, 3> nodes {};
    Index face = kNone;
};

/// Fan triangulation of every face loop. The apex of each fan is picked from the geometry alone
/// (largest smallest signed triangle area, ties to the lexicographically smallest position), so
/// the two cells sharing a face triangulate it identically whatever their loop orientation;
/// triangles of area below area_tol [m^2] (collinear vertices) are dropped: they contribute
/// nothing to the mean value weights.
std::vector<SurfaceTriangle> fan_triangulation(
    const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops, double area_tol);

/// Bounding-box diagonal of the nodes [m].
double cell_size(const std::vector<Vec3>& nodes);

} // namespace polycut::basis
