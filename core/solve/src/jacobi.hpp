// Jacobi and 3x3 node-block Jacobi set-ups of PCG (private to core/solve).
#pragma once

#include "polycut/solve/pcg.hpp"

#include <Eigen/Dense>
#include <vector>

namespace polycut::solve::detail {

/// inv_diag = 1 / diag(A); NonFinite or NotPositiveDefinite on a bad diagonal entry.
SolveStatus invert_diagonal(const SparseMatrix& A, Vector& inv_diag);

/// The inverses of A's 3x3 diagonal blocks (rows 3b..3b+2), by Cholesky (a diagonal block of an
/// SPD matrix is SPD); the trailing rows that fill no block get scalar Jacobi in inv_diag.
SolveStatus invert_node_blocks(
    const SparseMatrix& A, std::vector<Eigen::Matrix3d>& inv_blocks, Vector& inv_diag);

} // namespace polycut::solve::detail
