// Preconditioned conjugate gradients, warm-started, with Jacobi, 3x3 block-Jacobi or a lagged
// CHOLMOD factor as preconditioner (DESIGN.md sec. 4).
#pragma once

#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/sparse.hpp"

#include <memory>

namespace polycut::solve {

enum class Preconditioner { None, Jacobi, BlockJacobi3, LaggedCholesky };

struct PcgOptions {
    double relative_tolerance = 1e-6; ///< stop at ||r|| <= tol ||b|| (dimensionless)
    int max_iterations = 1000;
    Preconditioner preconditioner = Preconditioner::Jacobi;
    /// LaggedCholesky: refactor every this many solves (0 = only when needed)...
    int refactor_every = 0;
    /// ...or when a solve needed more iterations than this.
    int refactor_iterations = 50;
};

struct PcgResult {
    SolveStatus status = SolveStatus::Ok;
    int iterations = 0;
    double relative_residual = 0; ///< ||b - A x|| / ||b||
    bool refactored = false;      ///< the lagged factor was recomputed before this solve
};

/// PCG with a persistent preconditioner. x is used as the initial guess (warm start).
class PcgSolver {
public:
    explicit PcgSolver(PcgOptions options = {});
    ~PcgSolver();
    PcgSolver(PcgSolver&&) noexcept;
    PcgSolver& operator=(PcgSolver&&) noexcept;

    const PcgOptions& options() const;
    /// Forget the preconditioner (call after a sparsity pattern change).
    void reset();
    /// Solves A x = b from the initial guess x. A: symmetric positive definite, full storage.
    PcgResult solve(const SparseMatrix& A, const Vector& b, Vector& x);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve
