// Linear (P1) shape functions on a tetrahedron: the barycentric coordinates. Their gradients are
// constant, so one quadrature point integrates B^T C B exactly (002 sec. 3.1, eq. 3.4).
#pragma once

#include "polycut/basis/cell_integration.hpp"

#include <array>

namespace polycut::basis {

/// Gradients of the four barycentric coordinates (4 x 3) [1/m] of the tet X (VTK order);
/// row i is grad phi_i. Throws MeshError(cell = -1) when the tet has volume <= 0.
Eigen::Matrix<double, 4, 3> p1_gradients(const std::array<Vec3, 4>& X);

/// Barycentric coordinates (4) of point p in the tet X.
Eigen::Vector4d p1_shape(const std::array<Vec3, 4>& X, const Vec3& p);

/// One-point integration of a P1 tet: the centroid, weight = volume, lumped volume V/4 per node.
CellIntegration p1_integration(const std::array<Vec3, 4>& X);

} // namespace polycut::basis
