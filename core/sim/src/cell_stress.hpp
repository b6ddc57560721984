// Private: a cell's stress from its nodes' positions, for the VTU output and the octree's
// stress-based refinement.
#pragma once

#include "polycut/elasticity/material.hpp"
#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::sim {

/// Cauchy stress of cell c [Pa] from the rotation-free part of the least-squares affine fit of
/// its nodes' motion (small strain), in the cell's rest frame; `rotation` (if given) gets the
/// polar rotation of the fit (the identity when not `corotated`), which takes it to world space.
Mat3 cell_stress(const elasticity::Material& material, bool corotated, const mesh::Mesh& m,
    const std::vector<Vec3>& positions, Index c, Mat3* rotation = nullptr);

} // namespace polycut::sim
