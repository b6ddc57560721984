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
    NotConverged,        ///< iterative solver hit its iteration limit
    NonFinite,           ///< NaN or Inf in the input or the result
    NotReady,            ///< solve() called before a successful factorize()
};

const char* to_string(SolveStatus s);

} // namespace polycut::solve
