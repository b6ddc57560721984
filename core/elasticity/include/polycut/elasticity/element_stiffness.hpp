// Element stiffness Ke = sum_q w_q B_q^T C B_q of any cell type from its CellIntegration
// (000 eq. 9, 002 eq. 3.4 for P1).
#pragma once

#include "polycut/basis/cell_basis.hpp"
#include "polycut/basis/cell_integration.hpp"
#include "polycut/elasticity/material.hpp"

namespace polycut::elasticity {

/// Strain-displacement matrix B (6 x 3n) at one point from the gradients (n x 3) [1/m]; DOFs
/// ordered [x0 y0 z0 x1 ...], Voigt order as elasticity_matrix().
MatX strain_displacement(const MatX3& gradients);

/// Element stiffness (3n x 3n) [N/m], symmetric positive semi-definite with the six rigid modes
/// in its kernel. Up to 8 nodes computed block-wise: K_ij = sum_q w_q (lambda g_i g_j^T +
/// mu g_j g_i^T + mu (g_i . g_j) I), which equals sum_q w_q B^T C B; larger cells as one
/// rank-k product S^T S of the stacked rows sqrt(w_q) L^T B_q, C = L L^T.
/// With VolumetricRule::MeanDilatation (B-bar, Hughes 1980): K = sum_q w_q B_q^T C_dev B_q +
/// kappa V bbar bbar^T, C_dev = C - kappa m m^T the deviatoric part (kappa = lambda + 2 mu / 3
/// the bulk modulus, m = [1 1 1 0 0 0]^T), V = sum_q w_q and bbar = (1/V) sum_q w_q m^T B_q the
/// cell's mean divergence row (3n): equal to sum_q w_q Bbar_q^T C Bbar_q with the dilatation
/// of Bbar_q replaced by its cell mean. Same rigid-mode kernel; identical for one-point cells.
MatX element_stiffness(const basis::CellIntegration& ci, const Material& material,
    basis::VolumetricRule rule = basis::VolumetricRule::Full);

/// Adds BasisOptions::stabilization (tau) to the stiffness Ke (3n x 3n) of a polyhedral cell with
/// rest offsets dX (n x 3) from its node centroid and fit gradients G (rotation.hpp):
/// tau tr(Ke) / 3n (I - P) (x) I3, P the affine least-squares projection of node values
/// (docs/decisions/0053). Ke u is unchanged for affine u.
void stabilize_non_affine(MatX& Ke, const MatX3& dX, const MatX3& G, double tau);

} // namespace polycut::elasticity
