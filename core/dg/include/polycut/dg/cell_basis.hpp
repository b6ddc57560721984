// The per-cell polynomial basis of DG (003 sec. 6): all polynomials of total degree p (1 or 2)
// on one polyhedron, non-nodal, orthonormalised in L2(K) (docs/decisions/0020).
//
// Why orthonormal rather than the raw monomials {1, x, y, ..., z^p} of 003 sec. 6: the
// consistent DG mass matrix of a cell is rho int_K phi_i phi_j, which becomes rho |K| I, so the
// block-diagonal consistent mass of 003 sec. 5 is exactly diagonal (the integrators' diagonal
// mass path is exact, no lumping), and the coefficients of a thin sliver keep a condition number
// of the order of the cell's, instead of the (thickness / size)^(-2p) of the monomials.
// The monomials are taken in xi = (x - c) / h (c the cell's centroid, h its largest centroid-
// to-vertex distance) before Cholesky-orthonormalisation: phi_i = sum_j T(i, j) m_j(xi), with
// (1/|K|) int_K phi_i phi_j = delta_ij and phi_0 = 1, so coefficient 0 is the cell's mean.
#pragma once

#include "polycut/common/types.hpp"

#include <vector>

namespace polycut::dg {

/// Basis of one cell.
struct CellBasis {
    int degree = 1; ///< p
    Vec3 center = Vec3::Zero(); ///< c, the rest centroid [m]
    double scale = 1; ///< h [m]
    double volume = 0; ///< |K| [m^3]
    /// T (nb x nb): phi_i = sum_j T(i, j) m_j((x - c) / h), monomials of polynomial.hpp.
    MatX T;
    /// Moments of the monomials of xi over the cell, up to degree 2p [m^3].
    VecX moments;

    int size() const { return int(T.rows()); }
    /// Values phi_i(x) (nb), dimensionless.
    VecX values(const Vec3& x) const;
    /// Gradients (nb x 3) [1/m] at x.
    MatX3 gradients(const Vec3& x) const;
};

/// Number of basis functions of degree p: (p+1)(p+2)(p+3)/6 (4 for p = 1, 10 for p = 2).
int basis_size(int degree);

/// Basis of the polyhedron with outward face loops `loops` into `points`. Throws InputError for
/// a degree outside [1, 2]; MeshError (cell `cell`) for a cell of non-positive volume or whose
/// monomials are linearly dependent to round-off (a flat cell).
CellBasis make_cell_basis(const std::vector<Vec3>& points,
    const std::vector<std::vector<Index>>& loops, int degree, Index cell = kNone);

/// Coefficients (nb x 3) of the identity map x on the basis: the rest "positions" of the cell's
/// DOFs, X0 of 003 sec. 7 ("non-nodal basis functions"), by L2 projection (exact: x is in the
/// span). Row 0 is the centroid.
MatX3 rest_coefficients(const CellBasis& basis);

} // namespace polycut::dg
