// Sparse Cholesky by CHOLMOD (supernodal LL^T) behind a small interface (DESIGN.md sec. 4).
// CHOLMOD headers stay in the .cpp.
#pragma once

#include "polycut/solve/sparse.hpp"

#include <memory>

namespace polycut::solve {

/// Fill-reducing ordering used by CholmodSolver::analyze().
enum class Ordering {
    Auto, ///< CHOLMOD's default: AMD, and METIS too when AMD's fill is high; keeps the better
    Amd, ///< approximate minimum degree only (cheapest analysis)
    Metis, ///< nested dissection only (least fill on 3D meshes, slower analysis)
};

/// CHOLMOD LL^T. Analyze once per sparsity pattern, factorize per matrix, solve many times.
/// A matrix that is not positive definite is reported, never solved.
///
/// Each instance owns its own cholmod_common, so distinct instances may be used from distinct
/// threads; one instance is not thread-safe (solve() reuses a mutable workspace). The first
/// instance sets OpenBLAS to one thread unless OPENBLAS_NUM_THREADS is set (blas_threads.hpp).
/// A moved-from solver is empty (not ready) and restarts with Ordering::Auto when reused.
class CholmodSolver {
public:
    CholmodSolver();
    /// A solver that analyzes with the given ordering.
    explicit CholmodSolver(Ordering ordering);
    ~CholmodSolver();
    CholmodSolver(CholmodSolver&&) noexcept;
    CholmodSolver& operator=(CholmodSolver&&) noexcept;

    /// Symbolic analysis (fill-reducing ordering, supernodes) of A's pattern. A: symmetric,
    /// full storage (both triangles), square. Only the upper triangle is read (stype = +1).
    /// Throws polycut::InputError if A is not square or CHOLMOD fails (out of memory).
    void analyze(const SparseMatrix& A);
    /// Numeric factorization; analyzes first if the pattern is new. Returns NotPositiveDefinite
    /// when CHOLMOD stops at a non-positive pivot, NonFinite on NaN/Inf in A; after a failure
    /// ready() is false until the next successful factorize().
    SolveStatus factorize(const SparseMatrix& A);
    /// x = A^-1 b with the current factor. b: size(); x is resized to size(). No allocation
    /// after the first solve of a given size. NonFinite on NaN/Inf in b (x untouched).
    SolveStatus solve(const Vector& b, Vector& x) const;
    /// True after a successful factorize().
    bool ready() const;
    /// Number of rows of the analyzed pattern (0 before analyze()).
    long size() const;

    /// True if A has exactly the analyzed pattern (same size, column pointers, row indices).
    bool same_pattern(const SparseMatrix& A) const;
    /// Number of symbolic analyses done so far (re-analysis happens on pattern change).
    int analyses() const;
    /// Number of stored entries of the factor L (0 before analyze()).
    long factor_nonzeros() const;
    /// Floating-point operations of the last factorization, as estimated by CHOLMOD.
    double factor_flops() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve
