// One interface over CHOLMOD and the PCG variants for the integrators' SPD systems.
#pragma once

#include "polycut/integrate/options.hpp"
#include "polycut/solve/cg_relaxation.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <string>

namespace polycut::integrate {

/// Outcome of one linear solve.
struct LinearSolveResult {
    solve::SolveStatus status = solve::SolveStatus::Ok;
    int iterations = 0;
    double relative_residual = 0;
    bool budget_reached = false; ///< PCG stopped at SolverOptions::iteration_budget
    /// Set once when the solver had to change method (AMG unavailable: Jacobi from then on).
    std::string warning;
};

/// Solves A x = b for SPD A; PCG variants start from x (warm start), CHOLMOD ignores it.
class LinearSolver {
public:
    explicit LinearSolver(const SolverOptions& options);
    /// Forget factors and preconditioners (after a sparsity pattern change).
    void reset();
    /// After a cut renumbered the unknowns (solve::RowRemap): keep the preconditioner if it can
    /// be (AMG; solve::PcgSolver::remap_preconditioner). False: call
    /// reset().
    bool remap(const solve::RowRemap& m);
    /// PcgAmg: set the hierarchy up again if it was carried over cuts
    /// (solve::PcgSolver::request_refresh).
    void request_refresh() { m_pcg.request_refresh(); }
    /// PCG: forget the solutions kept for the projected start (a step was rolled back).
    void forget_solutions() { m_pcg.forget_solutions(); }
    LinearSolveResult solve(const solve::SparseMatrix& A, const solve::Vector& b, solve::Vector& x);
    /// PcgAmg: sets up the hierarchy for A ahead of the first solve (solve::PcgSolver::prepare).
    /// True when a set-up was wanted (an AMG solver).
    bool prepare(const solve::SparseMatrix& A);
    bool wants_prepare() const { return m_options.kind == LinearSolverKind::PcgAmg; }
    /// PcgAmg with rigid-body modes: node coordinates of the reduced DOFs (see
    /// solve::PcgSolver::set_coordinates) [m].
    void set_coordinates(const solve::Vector& coordinates) { m_pcg.set_coordinates(coordinates); }
    /// PCG: also stop at ||r|| <= tolerance (b's units) from the next solve on.
    void set_absolute_tolerance(double tolerance) { m_pcg.set_absolute_tolerance(tolerance); }
    /// PcgCellBlockJacobi: the starts of the reduced system's diagonal blocks.
    void set_blocks(std::vector<long> starts) { m_pcg.set_blocks(std::move(starts)); }
    /// PcgTwoLevel: the coarse space's prolongation (solve::PcgSolver::set_coarse_space).
    void set_coarse_space(const solve::SparseMatrix& P) { m_pcg.set_coarse_space(P); }
    bool wants_coarse_space() const { return m_options.kind == LinearSolverKind::PcgTwoLevel; }
    /// The AMG hierarchy wants node coordinates (PcgAmg with AmgOptions::rigid_body_modes).
    bool wants_coordinates() const {
        return m_options.kind == LinearSolverKind::PcgAmg && m_options.amg.rigid_body_modes;
    }
    const SolverOptions& options() const { return m_options; }
    /// Threads of the next solve (solve::PcgSolver::threads: 1 while a background set-up runs).
    int threads() const { return m_pcg.threads(); }

private:
    SolverOptions m_options;
    solve::CholmodSolver m_cholmod;
    solve::PcgSolver m_pcg;
    solve::CgRelaxation m_relaxation;
    std::vector<bool> m_no_fixed; ///< the reduced system has no fixed DOFs left
};

} // namespace polycut::integrate
