// Options, state and step report of the integrators.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/options/integrate.hpp"
#include "polycut/solve/sparse.hpp"

#include <string>
#include <vector>

namespace polycut::integrate {

/// Mutable simulation state.
struct State {
    MatX3 x; ///< world positions (#N x 3) [m]
    MatX3 v; ///< velocities (#N x 3) [m/s]
    double time = 0; ///< [s]
};

/// What a step did. step() never throws; problems are listed in `warnings`.
struct StepReport {
    double step_ms = 0; ///< wall time of the step [ms]
    double assembly_ms = 0; ///< of which assembly of K and f [ms]
    double solve_ms = 0; ///< of which linear solves [ms]
    int solver_iterations = 0; ///< PCG iterations (summed over Newton iterations)
    /// a linear solve stopped at SolverOptions::iteration_budget (`residual` says how far)
    bool solver_budget_reached = false;
    double residual = 0; ///< relative residual of the last linear solve (static: of equilibrium)
    int newton_iterations = 0; ///< static: nonlinear iterations
    solve::SolveStatus status = solve::SolveStatus::Ok;
    std::vector<std::string> warnings;
    bool rolled_back = false; ///< the state was restored to its value before the step
    /// energy_guard: substeps the step was split into (1 when it was not)
    int substeps = 1;
    /// Penalty points (contacts) in the last evaluation of the penalty field
    int penalty_points = 0;
    /// Penalty matrix entries that fell outside the sparsity pattern and were dropped (0 when
    /// every point's nodes share a cell)
    int penalty_entries_dropped = 0;
};

} // namespace polycut::integrate
