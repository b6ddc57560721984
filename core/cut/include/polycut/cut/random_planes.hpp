// Mesh builder by repeated plane splits (000 Fig. 2: a hex split by 30 random planes into 31
// convex cells of 8 to 32 nodes). The mesh stays conforming: edge nodes are shared, split faces
// are split for both cells.
#pragma once

#include "polycut/cut/cut_options.hpp"
#include "polycut/mesh/mesh.hpp"

namespace polycut::cut {

/// Options of split_by_random_planes.
struct RandomPlanesOptions {
    /// true: each plane splits one cell, picked at random with probability proportional to its
    /// volume, through a random point near its centroid (000 Fig. 2: n planes give n + 1 cells
    /// from one hex); false: each plane, through a random point of the mesh's bounding box,
    /// splits every cell it crosses.
    bool one_cell_per_plane = true;
    /// The plane point is the cell centroid plus a uniform offset of up to this fraction of the
    /// cell's bounding-box extent per axis.
    double offset = 0.25;
    CutOptions cut; ///< snapping
};

/// Splits a copy of `mesh` (any convex cells, e.g. mesh::hex_grid) by `planes` random planes
/// from a fixed `seed`; deterministic.
mesh::Mesh split_by_random_planes(
    const mesh::Mesh& mesh, int planes, unsigned seed, const RandomPlanesOptions& options = {});

} // namespace polycut::cut
