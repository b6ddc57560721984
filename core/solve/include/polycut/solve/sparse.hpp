// Sparse matrix type shared by assembly and solvers: compressed sparse column, double, full
// symmetric storage (both triangles), 32-bit indices.
#pragma once

#include <Eigen/SparseCore>

namespace polycut::solve {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Vector = Eigen::VectorXd;

/// Outcome of a linear solve.
enum class SolveStatus {
    Ok,
    NotPositiveDefinite, ///< factorization found a non-positive pivot (matrix indefinite)
    NotConverged, ///< iterative solver hit its iteration limit
    NonFinite, ///< NaN or Inf in the input or the result
    NotReady, ///< solve() called before a successful factorize()
};

/// Name of a status ("ok", "not_positive_definite", ...), for step reports.
const char* to_string(SolveStatus s);

/// y = A x for a symmetric A in full storage, computed row-wise as y_j = A(:,j) . x (a gather:
/// no scattered writes, one accumulator per row). A: n x n, x: n; y is resized to n (no
/// allocation when it already has n rows). y must not alias x.
void multiply_symmetric(const SparseMatrix& A, const Vector& x, Vector& y);

} // namespace polycut::solve
