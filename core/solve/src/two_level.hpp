// Private: a two-level (auxiliary-space) preconditioner for PCG (Preconditioner::TwoLevel): a
// block-Jacobi smoother over given diagonal blocks (the cells of a DG model) and a Galerkin
// coarse space given by a prolongation P (n x nc; for DG, the P1 field on the mesh's nodes,
// docs/decisions/0024), in the symmetric two-level form
//   B = W + (I - W A) P Ac^-1 P^T (I - A W),   W = omega D^-1,   Ac = P^T A P,
// which is symmetric positive definite for any SPD W and SPD Ac, also when A has changed since
// the set-up (a lagged A P and Ac): only the quality of B depends on how current they are.
// Applied with the stored products A P and (A P)^T, so one application costs two passes over
// A P (not A), the block products and one small CHOLMOD solve.
#pragma once

#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/sparse.hpp"

#include <vector>

namespace polycut::solve::detail {

/// Inverts the diagonal blocks of A (starts: ascending, first 0, last n) into `inverse` (packed
/// column-major blocks). NotReady for blocks that do not fit A, NonFinite, NotPositiveDefinite
/// (a block's LL^T fails).
SolveStatus invert_diagonal_blocks(
    const SparseMatrix& A, const std::vector<long>& starts, std::vector<double>& inverse);

class TwoLevelPreconditioner {
public:
    /// The prolongation P (n x nc, nc >= 1), copied. Drops the current set-up.
    void set_coarse_space(const SparseMatrix& P);
    /// Rows of the prolongation (0 without one).
    long space_rows() const { return m_P.rows(); }
    /// Smoother blocks (as PcgSolver::set_blocks) and weight omega (0 < omega).
    void set_smoother(const std::vector<long>& starts, double omega);
    /// Computes A P, Ac = P^T A P (plus 1e-10 of its diagonal: a P whose columns are dependent
    /// leaves Ac singular, and those directions are killed by P again) and Ac's factor, and
    /// the smoother from A. NotReady without a prolongation of A's size or without blocks.
    SolveStatus setup(const SparseMatrix& A);
    /// Refreshes only the smoother's blocks from A (the coarse part stays lagged).
    SolveStatus refresh_smoother(const SparseMatrix& A);
    /// z = B r. NotReady before a successful setup() of this size.
    SolveStatus apply(const Vector& r, Vector& z);
    /// Size of the last set-up (-1 if none).
    long size() const { return m_size; }
    long coarse_size() const { return m_P.cols(); }
    void clear();

private:
    void smooth(const Vector& r, Vector& out) const; ///< out = W r

    SparseMatrix m_P, m_PT, m_AP, m_APT;
    std::vector<long> m_starts;
    std::vector<double> m_inverse;
    double m_omega = 1.0;
    CholmodSolver m_coarse;
    long m_size = -1;
    Vector m_w, m_g, m_y, m_t;
};

} // namespace polycut::solve::detail
