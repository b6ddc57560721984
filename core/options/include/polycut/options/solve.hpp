// Settings of the algebraic multigrid preconditioner (hypre BoomerAMG, DESIGN.md sec. 4), in the
// options layer (docs/decisions/0051). hypre and MPI stay private to polycut_solve: plain numbers.
#pragma once

namespace polycut::solve {

/// Smoother of the AMG V-cycle: one pre- and one post-sweep per level (AmgOptions::sweeps), chosen
/// so that the cycle stays symmetric (PCG needs an SPD preconditioner).
enum class AmgSmoother {
    GaussSeidel, ///< forward Gauss-Seidel down, backward up (hypre relax types 13 / 14)
    L1Jacobi, ///< l1-scaled Jacobi both ways (hypre 18): one fused SpMV-like pass per sweep
    Chebyshev, ///< second-order Chebyshev polynomial of D^-1 A (hypre 16)
};

/// BoomerAMG set-up for a vector problem with `functions` unknowns per node, interleaved (DOF
/// `functions * node + component`, as the reduced elasticity systems are when whole nodes are
/// fixed). Defaults: nodal (systems) coarsening, HMIS, extended+i interpolation truncated to 4
/// entries per row, one level of aggressive coarsening, one V(1,1)-cycle of symmetric
/// Gauss-Seidel per application (a symmetric preconditioner, as PCG needs).
struct AmgOptions {
    /// Unknowns per node (3 for 3D elasticity). Used only when it divides the matrix size; else 1.
    int functions = 3;
    /// Strength threshold theta in (0, 1): j strongly influences i if -a_ij >= theta max_k -a_ik
    /// (on the node-block norms when functions > 1). hypre recommends ~0.5 in 3D.
    double strong_threshold = 0.5;
    /// Levels coarsened aggressively (HMIS with two paths, multipass interpolation): fewer levels
    /// and a cheaper set-up and cycle, at some cost in iterations.
    int aggressive_levels = 1;
    /// Maximum interpolation entries per row (0 = no truncation).
    int interpolation_max_elements = 4;
    /// Coarsest level size, solved directly (Gaussian elimination).
    int max_coarse_size = 64;
    /// Pre- and post-smoothing sweeps per level.
    int sweeps = 1;
    /// Smoother (see AmgSmoother).
    AmgSmoother smoother = AmgSmoother::GaussSeidel;
    /// GaussSeidel: relax the coarse points first on the way down and last on the way up
    /// (C/F ordering; the up-sweep stays the adjoint of the down-sweep).
    bool cf_order = false;
    /// Augment the interpolation with the three rigid-body rotations of the node coordinates given
    /// to PcgSolver::set_coordinates() (hypre's GM-2 variant, Baker, Kolev & Yang 2010, Numer.
    /// Linear Algebra Appl. 17: 495-517); the translations are already interpolated exactly by
    /// the unknown-based interpolation. Needs functions == 3; ignored without coordinates.
    bool rigid_body_modes = false;
    /// rigid_body_modes: maximum entries per row of each added interpolation block (0 = all).
    int rigid_body_max_elements = 4;
    /// Run polycut's own V-cycle over the hierarchy (copied out of hypre after its set-up) instead
    /// of hypre's: the same symmetric Gauss-Seidel cycle, but the down-sweep from zero and the
    /// residual read the matrix once together, and the finest level smooths with the current
    /// matrix instead of the set-up's. Only with GaussSeidel, one sweep, no cf_order (else
    /// hypre's cycle runs).
    bool fused_cycle = true;
    /// fused_cycle on a matrix whose unknowns come as whole nodes (3 per node, one 3x3-block
    /// pattern): smooth the finest level by 3x3 block Gauss-Seidel on a block-CSR copy refreshed
    /// once per solve (amg_cycle.hpp, "Node blocks"); false: point Gauss-Seidel on the matrix.
    /// Off by default: on the 5k-node organ (idle machine) the same iterations, and the copy
    /// costs more than the faster sweeps save (solve 8.7-8.9 -> 10.6-12.8 ms on one thread,
    /// mixed on two; docs/perf.md "Organ scale")
    bool node_blocks = false;
    /// A set-up that the lagged rule asks for (PcgOptions::refactor_iterations) runs on a worker
    /// thread and is installed exactly this many solves later, waiting for it if it is late (a
    /// fixed hand-over, so a replayed command log solves the same); the old hierarchy, carried
    /// over cuts, preconditions the solves in between. 0: set up inside the solve that asks
    /// (blocking it: ~100 ms on a 5k-node organ). The first set-up, and one after a size change
    /// that could not be carried over, is always in the foreground.
    int background_solves = 0;
    /// While a background set-up runs, the solves (and, through PcgSolver::threads(), the
    /// integrator's assembly) use one thread, leaving the other cores to the worker. On two cores
    /// a worker beside two step threads preempted one of them: every parallel region of the step
    /// waited for it (solves of 40-120 ms at 4-7 iterations on the 5k organ), and the worker,
    /// starved at its low priority, was still late at the hand-over (a blocking wait of up to
    /// 80 ms). The switches happen at fixed solves (the start and the hand-over), so replays
    /// stay deterministic.
    bool background_serial = true;
    /// A set-up that is asked for (the end of a cutting stroke, PcgSolver::request_refresh, or a
    /// solve that needed many iterations) starts on the worker only once this many solves have
    /// passed since the last cut that carried the hierarchy over: no set-up while a stroke cuts
    /// or its lips ring. Right after a stroke the solves need 5-14 iterations for ~15 ticks on
    /// the 5k organ whatever the hierarchy (a fresh one trims the peak from 12 to 9), and a
    /// set-up started then, or during the next stroke, put exactly those solves on one thread
    /// (background_serial): 35-55 ms steps, the worst ticks of a split stroke, against 17-31 ms
    /// on two threads. Counted in solves, so replays stay deterministic; a set-up on the
    /// refactor_every schedule is not held. 0: start at once.
    int refresh_delay = 20;
};

} // namespace polycut::solve
