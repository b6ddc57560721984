// Sparse matrix type shared by assembly and solvers: compressed sparse column, double, full
// symmetric storage (both triangles), 32-bit indices.
#pragma once

#include "polycut/common/sparse.hpp"

#include <Eigen/SparseCore>
#include <span>
#include <vector>

namespace polycut::solve {

using SparseMatrix = polycut::SparseMatrix; ///< defined in common (models hand it out)
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

/// How the unknowns of a system relate to those of an earlier one after a cut renumbered them
/// (issue 12 item 5: a preconditioner is carried over instead of set up again).
struct RowRemap {
    /// old_of[r]: the earlier row of row r, or -1 for a new unknown.
    std::vector<long> old_of;
    /// For new unknowns: where they come from, as weighted earlier rows (weights summing to 1,
    /// e.g. the same component of the node's uncut neighbours). CSR over the new rows:
    /// origin_ptr has old_of.size() + 1 entries, or none (new unknowns have no origin).
    std::vector<int> origin_ptr;
    std::vector<long> origin_row;
    std::vector<double> origin_weight;
};

/// y = A x for a symmetric A in full storage, computed row-wise as y_j = A(:,j) . x (a gather:
/// no scattered writes, one accumulator per row). A: n x n, x: n; y is resized to n (no
/// allocation when it already has n rows). y must not alias x.
/// threads > 1 splits the rows into static blocks (the same sums per row: the result does not
/// depend on the count).
void multiply_symmetric(const SparseMatrix& A, const Vector& x, Vector& y, int threads = 1);

/// ys[i] = A xs[i] for up to kMaxMultiply vectors in one pass over A: each entry of A is read
/// once for all of them (the products of the kept PCG solutions after a cut were four passes).
/// Every ys[i] equals multiply_symmetric(A, xs[i], ys[i]) to the bit. xs.size() == ys.size();
/// no ys[i] may alias an xs[j].
inline constexpr std::size_t kMaxMultiply = 32;
void multiply_symmetric_many(
    const SparseMatrix& A, std::span<const Vector> xs, std::span<Vector> ys, int threads = 1);

/// One pass over a symmetric K (full storage, n x n): A = a K + diag(d) on K's pattern and
/// y = K x (as multiply_symmetric). A must have K's sparsity pattern, compressed like K (e.g. a
/// copy of K); every diagonal entry must be stored. d, x: n; y is resized to n (no allocation
/// when it already has n rows) and must not alias x. Reads K once instead of twice (the implicit
/// Euler step's system matrix and its K v).
void scale_shift_multiply(const SparseMatrix& K, double a, const Vector& d, const Vector& x,
    SparseMatrix& A, Vector& y, int threads = 1);

} // namespace polycut::solve
