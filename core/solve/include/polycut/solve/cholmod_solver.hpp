// Sparse Cholesky by CHOLMOD (supernodal LL^T) behind a small interface (DESIGN.md sec. 4).
// CHOLMOD headers stay in the .cpp.
#pragma once

#include "polycut/solve/sparse.hpp"

#include <memory>

namespace polycut::solve {

/// CHOLMOD LL^T. Analyze once per sparsity pattern, factorize per matrix, solve many times.
/// A matrix that is not positive definite is reported, never solved.
class CholmodSolver {
public:
    CholmodSolver();
    ~CholmodSolver();
    CholmodSolver(CholmodSolver&&) noexcept;
    CholmodSolver& operator=(CholmodSolver&&) noexcept;

    /// Symbolic analysis (fill-reducing ordering, supernodes) of A's pattern. A: symmetric,
    /// full storage (both triangles), square.
    void analyze(const SparseMatrix& A);
    /// Numeric factorization; analyzes first if the pattern is new. Returns NotPositiveDefinite
    /// when CHOLMOD stops at a non-positive pivot.
    SolveStatus factorize(const SparseMatrix& A);
    /// x = A^-1 b with the current factor.
    SolveStatus solve(const Vector& b, Vector& x) const;
    /// True after a successful factorize().
    bool ready() const;
    /// Number of rows of the analyzed pattern (0 before analyze()).
    long size() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve
