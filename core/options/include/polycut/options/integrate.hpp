// Options of core/integrate: the integrator and its linear solver. Plain data in the options layer
// (docs/decisions/0051), the one place their defaults live: core/scene takes its defaults from
// them.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/options/elasticity.hpp"
#include "polycut/options/solve.hpp"

namespace polycut::integrate {

/// Which time integrator a step runs.
enum class IntegratorKind {
    Static, ///< equilibrium under the current loads (no inertia)
    ImplicitEuler, ///< backward Euler linearized once per step (DESIGN.md sec. 4)
    SemiImplicitEuler ///< symplectic Euler: v += h M^-1 f(x, v), x += h v (001, 003)
};

/// How a static step reaches equilibrium.
enum class StaticMode {
    Linear, ///< one solve with the rest stiffness (small strains)
    CorotatedFixedPoint, ///< K_R(x_k) x_{k+1} = f_ext + rotated rest forces (warped stiffness)
    CorotatedNewton, ///< quasi-Newton with tangent K_R (dR/dx neglected) + backtracking
};

/// Linear solver of the implicit systems.
enum class LinearSolverKind {
    Cholmod, ///< CHOLMOD LL^T, refactored at every solve
    PcgJacobi, ///< PCG, Jacobi preconditioner, warm-started
    PcgBlockJacobi, ///< PCG, 3x3 block-Jacobi preconditioner, warm-started
    /// PCG, block Jacobi over the model's DOF blocks (elasticity::Model::dof_blocks(): the
    /// coefficients of each DG cell); 3x3 blocks for a model without blocks
    PcgCellBlockJacobi,
    PcgLagged, ///< PCG preconditioned by a lagged CHOLMOD factor
    PcgIncompleteCholesky, ///< PCG preconditioned by a lagged incomplete Cholesky factor
    /// PCG preconditioned by one V-cycle of a lagged algebraic multigrid hierarchy (hypre
    /// BoomerAMG, systems AMG with 3 unknowns per node), set up again on the PcgLagged schedule
    PcgAmg,
    /// PCG preconditioned by a two-level method: block Jacobi over the model's DOF blocks as
    /// smoother, the model's coarse space (elasticity::Model::coarse_space(); DG: P1 on the
    /// nodes) as a lagged Galerkin coarse level (docs/decisions/0024); cell block Jacobi for a
    /// model without a coarse space
    PcgTwoLevel,
    /// Unpreconditioned CG relaxation of seed 002 sec. 3.1 (fixed DOFs eliminated; stops at
    /// ||r|| < tol ||b||), warm-started; the solver Nienhuys' static cutting simulator used.
    CgRelaxation,
};

/// Solutions a projected PCG start keeps by default (SolverOptions::start_vectors): on the
/// sagging 5k organ (160 steps from rest) 4 gave 167 iterations, 6 gave 153 and 8 144, against 270
/// with the extrapolated start, each kept vector costing two dot products and an axpy per solve
/// (docs/perf.md).
inline constexpr int kProjectedStartVectors = 4;

/// Linear solver settings.
struct SolverOptions {
    LinearSolverKind kind = LinearSolverKind::PcgJacobi;
    double relative_tolerance = 1e-6; ///< PCG: stop at ||r|| <= tol ||b||...
    /// ...or (implicit Euler) at ||r|| <= load_tolerance h ||f_ext|| (dimensionless; 0 = off):
    /// the residual force below this fraction of the applied loads. The right-hand side
    /// h (f_ext + f_int - ...) vanishes as a body settles under its loads, so a tolerance
    /// relative to it alone asks ever more iterations of a body at rest (organ_500 at 1 kHz: 4
    /// while sagging, 13 once settled). Off by default: a floor stops a solve before it resolves
    /// what the relative tolerance would (a damped beam solved at 1e-10 then settles only to
    /// ~1e-4 of its sag); scenes at loose tolerances and high rates set it
    double load_tolerance = 0;
    int max_iterations = 2000; ///< PCG iteration limit
    /// PCG: stop after this many iterations and step with the iterate (0 = off;
    /// solve::PcgOptions::iteration_budget): a bounded solve cost, judged by the error it leaves
    int iteration_budget = 0;
    /// PcgLagged, PcgIncompleteCholesky, PcgAmg: refactor (AMG: set up again) every k solves
    /// (0 = on demand)
    int refactor_every = 0;
    /// PcgLagged, PcgIncompleteCholesky, PcgAmg: refactor when a solve took more iterations
    /// (PcgAmg: and more than 1.5x the first solve after the last set-up,
    /// solve::PcgOptions::refactor_growth)
    int refactor_iterations = 50;
    bool background_refactor = false; ///< PcgLagged: refactor on a worker thread
    /// PCG: start each solve from the Galerkin projection of the system onto the span of the
    /// last this many solutions (0 = off; solve::PcgOptions::start_vectors)
    int start_vectors = 0;
    /// PcgAmg: hierarchy settings (with rigid_body_modes the integrator passes the current node
    /// positions of the free DOFs before each solve)
    solve::AmgOptions amg {};
    /// Threads of the PCG matrix passes (Integrator sets it from IntegratorOptions::threads)
    int threads = 1;
};

/// Integrator settings.
struct IntegratorOptions {
    IntegratorKind kind = IntegratorKind::ImplicitEuler;
    double dt = 0.01; ///< time step h [s]
    elasticity::ForceMode force_mode = elasticity::ForceMode::Corotated; ///< dynamics
    StaticMode static_mode = StaticMode::CorotatedNewton; ///< Static only
    double static_tolerance = 1e-8; ///< Static: stop at ||r|| <= tol ||f_ext|| (dimensionless)
    int static_max_iterations = 100;
    Vec3 gravity = Vec3::Zero(); ///< [m/s^2]
    /// A step whose displacement exceeds this many times the mesh's bounding-box diagonal is
    /// treated as diverged and rolled back.
    double divergence_factor = 100.0;
    /// A step after which some cell is stretched by more than this factor (the longest distance
    /// from a cell's first node to its other nodes, deformed over the same at rest) is treated
    /// as an explosion and rolled back. Tissue tears long before 10x; an unstable step (a bad cell
    /// after a cut, a stiff explicit spring) reaches it within a few ticks (dimensionless).
    double stretch_limit = 10.0;
    /// ...and whose stretch grew by more than this factor in the step (per cell: the cell's
    /// stretch after the step over its stretch before it). A cell with a zero-energy mode after
    /// a cut, or a numerically unstable step, goes past the limit in one or two steps; soft
    /// tissue that sags far under gravity stretches past it a few percent per step, which is
    /// the model's answer, not an explosion (issue 17 item 4, docs/decisions/0013).
    double stretch_growth = 2.0;
    /// ImplicitEuler with PCG: start from the linear extrapolation 2 dv_{n-1} - dv_{n-2} of the
    /// last two velocity increments instead of dv_{n-1} (fewer iterations on smooth motion).
    bool extrapolate_warm_start = false;
    /// ImplicitEuler: assemble the corotated stiffness K_R (and the system matrix) every k steps
    /// and reuse it in between (forces and rotations are still evaluated every step, so the
    /// equilibrium is exact; only the step's linearization lags by up to k - 1 steps). 1 = every
    /// step (the design's "linearized once per step"). Pays at haptic rates, where a step moves
    /// the rotations by very little (docs/perf.md "Organ scale").
    int stiffness_every = 1;
    /// ImplicitEuler: a step after which the total energy (kinetic + elastic + gravity potential)
    /// exceeds its value before by more than the work of the external forces is redone as two
    /// half steps, recursively, up to 2^max_energy_halvings substeps; a gain that survives them
    /// is taken out of the kinetic energy (velocities scaled down) and reported. Backward Euler
    /// is dissipative, but linearized once per step with the corotated stiffness (dR/dx
    /// dropped) it can gain energy when cells rotate far within a step (soft, near-incompressible
    /// tissue at large dt), and the affine-fit rotation of hexes and polyhedra makes their force
    /// slightly non-conservative (issue 17 item 4, docs/decisions/0013). Costs two energy
    /// evaluations per step.
    bool energy_guard = false;
    int max_energy_halvings = 3;
    /// Threads for assembly and the solver's matrix passes (1 = serial). A step's result is
    /// deterministic for a given count; counts differ by the order of sums (round-off).
    int threads = 1;
    SolverOptions solver;
};

} // namespace polycut::integrate
