// Trilinear (Q1) shape functions on a hexahedron through the isoparametric map from [-1, 1]^3
// (VTK node order), integrated with tensor Gauss-Legendre rules; distorted hexes are fine as long
// as the Jacobian stays positive at the quadrature points.
#pragma once

#include "polycut/basis/cell_integration.hpp"

#include <array>

namespace polycut::basis {

/// Reference coordinates of the 8 VTK hex nodes (8 x 3), entries +-1.
const Eigen::Matrix<double, 8, 3>& q1_reference_nodes();

/// Trilinear shape functions (8) at reference point xi in [-1, 1]^3.
Eigen::Matrix<double, 8, 1> q1_shape(const Vec3& xi);

/// Reference gradients d N_i / d xi (8 x 3) at xi.
Eigen::Matrix<double, 8, 3> q1_reference_gradients(const Vec3& xi);

/// Physical point of reference point xi on the hex X [m].
Vec3 q1_map(const std::array<Vec3, 8>& X, const Vec3& xi);

/// Integration of a Q1 hex with n x n x n Gauss points (n = 2 by default, exact for the
/// stiffness of a parallelepiped). gradients[q] are physical gradients (8 x 3) [1/m]; the lumped
/// volume of node i is the integral of N_i. Throws MeshError(cell = -1) when the Jacobian
/// determinant is <= 0 at a quadrature point.
CellIntegration q1_integration(const std::array<Vec3, 8>& X, int n = 2);

} // namespace polycut::basis
