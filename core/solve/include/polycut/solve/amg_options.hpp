// Settings of the algebraic multigrid preconditioner (hypre BoomerAMG, DESIGN.md sec. 4). hypre
// and MPI stay private to polycut_solve: this header only holds plain numbers.
#pragma once

namespace polycut::solve {

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
};

} // namespace polycut::solve
