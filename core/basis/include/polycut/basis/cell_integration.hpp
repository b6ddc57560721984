// The one interface between cell types and the shared elasticity code (DESIGN.md sec. 1): a cell
// type provides its shape-function gradients at its quadrature points and the lumped volume per
// node; stiffness, mass, corotation and assembly are computed from this alone.
#pragma once

#include "polycut/common/types.hpp"

#include <vector>

namespace polycut::basis {

/// Shape-function gradients of one cell at its quadrature points, in rest space.
struct CellIntegration {
    /// Quadrature points [m] (#Q), in rest space.
    std::vector<Vec3> points;
    /// Quadrature weights [m^3] (#Q); they sum to the cell volume.
    std::vector<double> weights;
    /// gradients[q] is (#nodes x 3) [1/m]: row i is grad phi_i at points[q]; node order is the
    /// cell's `nodes` order.
    std::vector<MatX3> gradients;
    /// Volume attributed to each node for lumped mass [m^3] (#nodes); sums to the cell volume.
    VecX lumped_volume;
};

} // namespace polycut::basis
