// Options of the cell-splitting cutter (seed 000 sec. 4-5). All tolerances are relative
// (dimensionless) unless a unit is given.
#pragma once

#include "polycut/common/types.hpp"

#include <array>

namespace polycut::cut {

/// A sweep triangle: three corner positions [m] (rest or world space, as the call says).
using Triangle = std::array<Vec3, 3>;

/// Tolerances of the cutter.
struct CutOptions {
    /// Snapping distance, relative to the local cell thickness h = 6 V / A of the thinnest cell
    /// around a node: a node closer than snap * h to a cutting plane counts as lying on it, so no
    /// edge node is created next to it (no needles, 000 sec. 4 and 5.1).
    double snap = 1e-3;
    /// Snapping distance of the sweep triangles' side planes (the plane through an edge of the
    /// triangle, perpendicular to it, that clips the faces lying in the sweep plane), relative
    /// to the mean cell size of the mesh the cutter was made for (cube root of the mean cell
    /// volume): a node this close to a side plane counts as on it. The blade's edges (its tip,
    /// the start and the end of a stroke) reach the rest mesh through an affine fit of a
    /// deforming body and arrive ~1-2 % of a cell beside grid nodes they were meant to pass
    /// through; clipping there left strips of faces and nodes 0.1-0.2 mm apart whose cells had
    /// near-zero-energy modes (issue 12, docs/decisions/0007). The crack front moves by at most
    /// this much.
    double edge_snap = 0.03;
    /// A sweep triangle whose area is below min_area * L^2 (L: rest bounding-box diagonal of the
    /// mesh) or whose shortest altitude is below min_area * L is rejected as degenerate.
    double min_area = 1e-10;
    /// Triangle corners farther than max_extent * L from the mesh's bounding-box centre are
    /// rejected ("huge coordinates").
    double max_extent = 1e3;
    /// After each cut call, take out of the changed cells the nodes that lie strictly inside a
    /// straight edge of every face using them (earlier crack-front positions): same geometry,
    /// fewer DOFs and smaller cells on progressive cuts.
    bool coarsen = true;
    /// Before coarsening, merge Cut faces of a changed cell that lie in one plane (to round-off),
    /// share one chain of edges and form a convex polygon together: the corners of each tick's
    /// crack faces then lie on straight edges and coarsening removes them.
    bool merge_cut_faces = true;
    /// Insert a pocket node when a cut polygon covers no node that could separate (000 sec. 5.2).
    bool pockets = true;
    /// Cells a call leaves with a rest volume below sliver_volume * (volume of their largest
    /// interior face neighbour) are merged with the neighbour whose union with them is convex
    /// up to round-off (000 sec. 4); slivers with no such neighbour are kept and counted.
    double sliver_volume = 1e-3;
    /// Merge slivers (see sliver_volume).
    bool merge_slivers = true;
    /// Convexity tolerance used when checking a merged cell, relative to its bounding-box
    /// diagonal.
    double convex_tol = 2e-2;
};

} // namespace polycut::cut
