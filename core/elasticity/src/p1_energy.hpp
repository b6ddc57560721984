// Closed-form corotated energy of a P1 tet (the energy guard's hot path, decision 0013): from
// the cached gradients instead of the generic 1/2 u^T Ke u with a 12 x 12 product per cell.
// Internal to polycut_elasticity.
#pragma once

#include "p1_batch.hpp"

namespace polycut::elasticity::detail {

/// Energy [J] of one tet at x (#N x 3, row-major) [m]: V (mu eps:eps + lambda / 2 tr(eps)^2)
/// with eps = sym(R^T F - C0), F = sum_i x_i g_i^T, the same strain as the force kernels, so
/// equal to 1/2 u^T Ke u up to round-off. Corotated: R is the polar rotation of F, warm-started
/// from `R` and returned in it; linear: R = I. tet.rotation and tet.scatter are not read.
double p1_energy(
    const P1TetView& tet, double lambda, double mu, const double* x, bool corotated, Mat3& R);

} // namespace polycut::elasticity::detail
