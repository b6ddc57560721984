// Private: one interface over the direct and iterative solvers, so the integrators do not care
// which one a scene picked.
#pragma once

#include "polycut/integrate/integrator.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

namespace polycut::integrate::detail {

struct LinearResult {
    solve::SolveStatus status = solve::SolveStatus::Ok;
    int iterations = 0;
    double relative_residual = 0;
    bool refactored = false;
};

class LinearSystem {
public:
    LinearSystem(SolverKind kind, const solve::PcgOptions& pcg);
    /// Forget factorizations and preconditioners (pattern or size change).
    void reset();
    /// Solves A x = b; x is the initial guess for iterative solvers. `matrix_changed` false lets
    /// the direct solver reuse its factor.
    LinearResult solve(const solve::SparseMatrix& A, const VecX& b, VecX& x, bool matrix_changed);

private:
    SolverKind m_kind;
    solve::CholmodSolver m_cholmod;
    solve::PcgSolver m_pcg;
    VecX m_residual;
};

} // namespace polycut::integrate::detail
