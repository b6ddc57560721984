// Per-cell rotation for corotation (DESIGN.md sec. 1; 000 sec. 3.6): the rotation of the polar
// decomposition of the least-squares affine fit x ~ A X + t of the cell's nodes. With the fit
// gradients G (n x 3) of a cell, A = sum_i x_i G_i^T; for a tet G are the P1 gradients and A is
// the deformation gradient.
#pragma once

#include "polycut/common/types.hpp"

#include <span>

namespace polycut::elasticity {

/// Fit gradients G (n x 3) [1/m] of rest points X (n >= 4, spanning 3D): row i is
/// (sum_j dX_j dX_j^T)^-1 dX_i with dX = X - centroid, so that A = sum_i x_i G_i^T is the
/// least-squares affine fit. Returns false if the points do not span 3D.
bool fit_gradients(std::span<const Vec3> rest, MatX3& G);

/// Polar rotation of A (det R = +1), warm-started from `guess` (the last step's rotation):
/// scaled Newton iterations X <- (g X + X^-T / g) / 2 (Higham 1986) on guess^T A, which is near
/// the identity after a small step, so 1-3 iterations suffice. Falls back to the SVD
/// (geometry::polar_rotation) for inverted or degenerate A.
Mat3 polar_rotation_warm(const Mat3& A, const Mat3& guess);

} // namespace polycut::elasticity
