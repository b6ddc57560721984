// Preconditioned conjugate gradients, warm-started, with Jacobi, 3x3 block-Jacobi, a lagged
// CHOLMOD factor, a lagged incomplete Cholesky factor or a lagged algebraic multigrid hierarchy
// (hypre BoomerAMG) as preconditioner (DESIGN.md sec. 4).
#pragma once

#include "polycut/solve/amg_options.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/sparse.hpp"

#include <memory>
#include <string>
#include <vector>

namespace polycut::solve {

/// PCG preconditioners. LaggedCholesky, IncompleteCholesky and Amg keep their factor / hierarchy
/// between solves and refresh it on the schedule of PcgOptions (refactor_every /
/// refactor_iterations). Amg: one V-cycle of hypre BoomerAMG (systems AMG, see AmgOptions).
/// BlockJacobi: the inverses of the diagonal blocks set by set_blocks() (per DG cell, say); 3x3
/// blocks (BlockJacobi3) while none are set. TwoLevel: that block Jacobi as the smoother of a
/// Galerkin coarse space P (set_coarse_space(); for DG the P1 field on the mesh nodes,
/// docs/decisions/0024), B = W + (I - W A) P (P^T A P)^-1 P^T (I - A W); its coarse part is lagged
/// like the CHOLMOD factor; BlockJacobi while no P of A's size is set.
enum class Preconditioner {
    None,
    Jacobi,
    BlockJacobi3,
    LaggedCholesky,
    IncompleteCholesky,
    Amg,
    BlockJacobi,
    TwoLevel,
};

/// Name of a preconditioner ("none", "jacobi", "block_jacobi3", "lagged_cholesky",
/// "incomplete_cholesky", "amg", "block_jacobi", "two_level").
const char* to_string(Preconditioner p);

struct PcgOptions {
    double relative_tolerance = 1e-6; ///< stop at ||r|| <= tol ||b|| (dimensionless)...
    /// ...or at ||r|| <= this (in b's units; 0 = none): a floor for right-hand sides that vanish,
    /// as a time step's does when the body settles (set per solve: set_absolute_tolerance())
    double absolute_tolerance = 0;
    int max_iterations = 1000;
    /// Stop after this many iterations and return the iterate as the solution (status Ok,
    /// PcgResult::budget_reached; 0 = no budget): an inexact solve with a bounded cost, as
    /// real-time simulators run CG for a fixed count (SOFA's CGLinearSolver `iterations`). PCG's
    /// iterate minimizes the error's A-norm over x0 + the Krylov space, so it is never further
    /// from the solution in that norm than the start (or zero, whichever PCG began from). A
    /// budget below refactor_iterations turns the lagged set-up rule off: the hierarchy or
    /// factor is renewed by refactor_every, request_refresh() or a size change only.
    int iteration_budget = 0;
    Preconditioner preconditioner = Preconditioner::Jacobi;
    /// LaggedCholesky, IncompleteCholesky, Amg: refactor (AMG: redo the set-up) every this many
    /// solves (0 = only when needed)...
    int refactor_every = 0;
    /// ...or when a solve needed more iterations than this and more than refactor_growth times
    /// the first solve after the last set-up.
    int refactor_iterations = 50;
    /// LaggedCholesky (foreground), Amg: a solve must also take more than this factor times the
    /// iterations of the first solve after the last set-up to ask for a new one, so a fresh
    /// factor or hierarchy that does no better is kept (0 = refactor_iterations alone).
    double refactor_growth = 1.5;
    /// Amg: hierarchy settings.
    AmgOptions amg {};
    /// Threads for the matrix passes: SpMV and, with Amg's fused cycle, the finest level's
    /// smoother (hybrid Gauss-Seidel across T row blocks). Deterministic for a given count; 1 =
    /// serial.
    int threads = 1;
    /// LaggedCholesky: refactor on a worker thread (BackgroundCholesky) instead of inside
    /// solve(). Until the new factor is ready, solve() keeps using the old one, or
    /// BlockJacobi3 if the old one has the wrong size (after a cut).
    bool background_refactor = false;
    /// TwoLevel: weight omega of the block-Jacobi smoother W = omega D^-1 (dimensionless)
    double two_level_weight = 1.0;
    /// TwoLevel: invert the smoother's blocks of every solve's matrix (true) or only at the
    /// lagged set-up of the coarse part (false)
    bool two_level_fresh_smoother = true;
    /// Start each solve from the Galerkin projection of A x = b onto the span of the last this
    /// many solutions (0 = off, at most 32; the given x while none is kept; Fischer 1998, see
    /// src/start_space.hpp)
    int start_vectors = 0;
};

struct PcgResult {
    SolveStatus status = SolveStatus::Ok;
    int iterations = 0;
    /// ||b - A x|| / ||b||, with PCG's recursively updated residual (equal to the true one up to
    /// round-off)
    double relative_residual = 0;
    /// ||b - A x0|| / ||b|| of the start the iterations began from (the given x, its
    /// projection, or zero when either was worse than zero in the A-norm)
    double start_residual = 0;
    bool refactored = false; ///< the lagged factor was recomputed before this solve
    /// PcgOptions::iteration_budget stopped the iterations before the tolerance was met
    /// (relative_residual says how far)
    bool budget_reached = false;
    /// Preconditioner actually applied (BlockJacobi3 while a background factor is pending).
    Preconditioner used = Preconditioner::None;
};

/// PCG with a persistent preconditioner. x is used as the initial guess (warm start).
/// Work vectors live in the solver and are reused while the size stays the same, so a solve
/// allocates nothing after the first one (except when refactoring the lagged factor).
class PcgSolver {
public:
    /// PcgOptions::absolute_tolerance for the following solves (>= 0, in b's units).
    void set_absolute_tolerance(double tolerance);
    explicit PcgSolver(PcgOptions options = {});
    ~PcgSolver();
    PcgSolver(PcgSolver&&) noexcept;
    PcgSolver& operator=(PcgSolver&&) noexcept;

    const PcgOptions& options() const;
    /// Forget the preconditioner (call after a sparsity pattern change).
    void reset();
    /// After a cut renumbered the unknowns (RowRemap: row r of the new system was old_of[r] of
    /// the old one, -1 for a new unknown, with the new unknowns' origins): keep the AMG hierarchy,
    /// carried over to the new numbering, instead of setting it up again (issue 12 item 5: a cut
    /// must not cost a blocking set-up; the lagged set-up rule sets up again when the solves need
    /// it). False when the preconditioner cannot be kept (not AMG, no hierarchy): then call
    /// reset().
    bool remap_preconditioner(const RowRemap& m);
    /// Amg: when the hierarchy was carried over cuts since its set-up (remap_preconditioner),
    /// the next solve sets it up again (in the background with AmgOptions::background_solves,
    /// like a set-up the iteration count asks for). The end of a stroke asks for it: the carried
    /// coarse operators still couple the lips, and as the cut opens the solves grew from ~5 to
    /// 20-30 iterations on the 5k organ. A background set-up starts AmgOptions::refresh_delay
    /// solves after the last cut (the ringing lips right after a stroke need many iterations
    /// whatever the hierarchy, and a set-up would put those solves on one thread). No-op
    /// otherwise.
    void request_refresh();
    /// Forgets the solutions kept for the projected start (PcgOptions::start_vectors): a step
    /// was rolled back. reset() forgets them too; remap_preconditioner() carries them to the new
    /// unknowns (their products with A are recomputed by the next solve).
    void forget_solutions();
    /// Solves A x = b from the initial guess x. A: symmetric positive definite, full storage.
    /// x: initial guess, replaced by zero if its size differs from A's or it is not finite, and
    /// by the projection onto the kept solutions with PcgOptions::start_vectors > 0;
    /// b = 0 gives x = 0 in 0 iterations. Status NotConverged at max_iterations (x is the last
    /// iterate; with a foreground lagged factor that was not fresh, it is refactored once and
    /// PCG goes on with a new budget), NotPositiveDefinite if a search direction has
    /// p^T A p <= 0 or a preconditioner setup meets a non-positive pivot, NonFinite on NaN/Inf
    /// in b or along the iteration. Throws InputError on mismatched sizes.
    PcgResult solve(const SparseMatrix& A, const Vector& b, Vector& x);
    /// Amg: sets up the hierarchy for A now, as the next solve() would if it has none, so that
    /// the solve finds it ready (a scene load prepares the first step's set-up off the tick).
    /// The next solve of A proceeds exactly as without this call. No-op for the other
    /// preconditioners or when a hierarchy of A's size exists. Status of the set-up.
    SolveStatus prepare(const SparseMatrix& A);

    /// Installs a factor (e.g. from BackgroundCholesky::take()) as the lagged preconditioner and
    /// restarts the refactor schedule. Used by LaggedCholesky only.
    void set_preconditioner_factor(CholmodSolver&& factor);
    /// Background mode: blocks until a pending background factorization has finished, then
    /// installs it (the next solve reports refactored). No-op otherwise.
    void finish_background_refactor();
    /// Amg with AmgOptions::rigid_body_modes: node coordinates of the DOFs (n: per DOF the
    /// coordinate of its node along the DOF's component, interleaved like the DOFs) [m], used by
    /// the next hierarchy set-up. Copied; ignored by the other preconditioners.
    void set_coordinates(const Vector& coordinates);
    /// BlockJacobi: where the diagonal blocks start (ascending, first 0, last n = the size; e.g.
    /// the DOFs of each DG cell). Copied; used from the next solve on.
    void set_blocks(std::vector<long> starts);
    /// TwoLevel: the prolongation P (n x nc) from the coarse space to the unknowns. Copied; the
    /// next solve sets the preconditioner up again.
    void set_coarse_space(const SparseMatrix& P);
    /// Threads the next solve's matrix passes use: PcgOptions::threads, or 1 while a background
    /// set-up runs (AmgOptions::background_serial). The integrator's assembly follows it.
    int threads() const;
    /// Number of lagged factorizations (or AMG set-ups) done so far (foreground and background).
    int refactorizations() const;
    /// Amg: levels of the current hierarchy (0 before the first set-up).
    int amg_levels() const;
    /// Amg: levels the cycle smooths on several threads (hybrid Gauss-Seidel: the finest, and
    /// each coarse level of at least 20,000 entries); 0 on one thread.
    int amg_threaded_levels() const;
    /// Why the preconditioner set-up last returned NotReady (e.g. hypre/MPI unusable), or "".
    const std::string& setup_error() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve
