// Steps an elasticity::Model (ElasticModel, dg::DgModel) in time or to equilibrium (DESIGN.md sec.
// 4). A step never throws: on a non-finite value, a solver failure or divergence it restores the
// state it started from and says why in the StepReport (MuJoCo-style warnings, STYLE.md).
#pragma once

#include "polycut/elasticity/model.hpp"
#include "polycut/integrate/linear_solver.hpp"
#include "polycut/integrate/options.hpp"
#include "polycut/integrate/penalty.hpp"
#include "polycut/integrate/springs.hpp"
#include "polycut/solve/background_cholesky.hpp"

#include <memory>

namespace polycut::integrate {

/// Integrator over a model it does not own (the model must outlive it).
class Integrator {
public:
    Integrator(elasticity::Model& model, const IntegratorOptions& options);

    const IntegratorOptions& options() const { return m_options; }
    /// The rest state: x = X, v = 0, time 0.
    State rest_state() const;
    /// External nodal forces (3#N) [N], applied in addition to gravity; an empty vector means
    /// none. Forces on fixed DOFs are ignored.
    void set_external_forces(VecX f_ext);
    /// Penalty springs acting from the next step on (grabs): their force and their stiffness
    /// enter the step (implicit in ImplicitEuler and Static, per-node implicit in
    /// SemiImplicitEuler), so they are stable for any stiffness. Replaces the previous set.
    void set_springs(std::vector<NodeSpring> springs);
    /// Penalty forces evaluated inside every (sub)step from its start state (contact,
    /// penalty.hpp): their stiffness and friction damping enter the system matrix as 3x3 blocks
    /// (implicit Euler, static) or per node (semi-implicit Euler). nullptr: none. Not owned;
    /// must outlive the steps it is set for.
    void set_penalty_field(PenaltyField* field) { m_penalty = field; }
    /// Advances `state` by one step (dt; Static: to equilibrium). Never throws.
    StepReport step(State& state);
    /// Implicit Euler with an AMG-preconditioned PCG: sets up the hierarchy for the system the
    /// next step from `state` solves (A = (1 + h alpha) M + (h beta + h^2) K(x), without
    /// springs or contact), so that the first step does not pay it: a scene load does it off
    /// the tick (the 5k organ's first server tick took 150-260 ms). Its assembly at state.x is
    /// kept for the next step if that starts from the same positions, so the step gives the
    /// same result, bit for bit, as without this call. No-op otherwise; never throws. True when
    /// it set up.
    bool prepare(const State& state);
    /// After a burst of cuts (the end of a stroke): the preconditioner carried over them is
    /// set up again from the next step's matrix, in the background where the solver allows it
    /// (LinearSolver::request_refresh). Applies from the next step; the results of a replay are
    /// the same.
    void refresh_preconditioner() { m_solver.request_refresh(); }
    /// Total energy [J]: kinetic 1/2 v^T M v + elastic (force mode of the options).
    double energy(const State& state) const;
    /// Largest stretch of any cell in positions `x` (#N x 3) [m]: max over cells of the largest
    /// distance from the cell's first node to another node, deformed over the same at rest (1
    /// at rest and under rigid motion). A step that leaves a cell above options.stretch_limit and
    /// more than options.stretch_growth times its own stretch before the step is rolled back.
    double max_cell_stretch(const MatX3& x) const;

    /// PcgLagged: the lagged factor's life after a sparsity pattern change (a cut). The first
    /// factor is computed on the first solve; after a pattern change, analysis and factorization
    /// of the new matrix run on a worker thread while PCG with block Jacobi carries the solves,
    /// and the new factor takes over after a fixed number of solves (handover_solves(), a
    /// function of the system size only, so a replay gives the same states; if the factor is
    /// late the solve waits for it). Refactorizations the iteration count asks for run the same
    /// way, the old factor carrying the solves in between.
    struct LaggedStatus {
        int foreground_factorizations = 0; ///< factorizations done inside a solve
        int background_factorizations = 0; ///< factorizations handed to the worker thread
        int bridged_solves = 0; ///< solves carried by block Jacobi while a new pattern factors
        int waits = 0; ///< handovers that had to wait for the worker
        bool pending = false; ///< a background factorization is under way
    };
    const LaggedStatus& lagged_status() const { return m_lagged_status; }
    /// Solves between starting a background factorization of an n-DOF system and installing it.
    static int handover_solves(Index n);

private:
    void ensure_topology(StepReport& report);
    /// How the model's reduced DOFs relate to those of m_dof_map_then after a cut that kept
    /// the node ids (node_map null) or renumbered them by node_map (old id -> new id), with
    /// origins for the new DOFs (from the new pattern in m_A).
    solve::RowRemap row_remap(const std::vector<Index>* node_map) const;
    bool step_implicit(State& s, StepReport& report, double h);
    /// step_implicit with options().energy_guard: halves h while a step gains energy.
    bool step_implicit_guarded(State& s, StepReport& report, double h, int depth);
    /// Kinetic + elastic + gravity potential (relative to rest) [J].
    double total_energy(const State& s) const;
    bool step_semi_implicit(State& s, StepReport& report);
    bool step_static(State& s, StepReport& report);
    /// Reduced f_ext + gravity (#free), into m_fext_r.
    void external_reduced();
    double assemble(const MatX3& x, elasticity::ForceMode mode, bool with_K, StepReport& report);
    bool linear_solve(const solve::SparseMatrix& A, const VecX& b, VecX& x, StepReport& report);
    /// The free entries of a per-node array (#N x 3) as a reduced vector (#free).
    void gather_free(const MatX3& full, VecX& reduced) const;
    /// Hands the free DOFs' current node positions to an AMG solver that wants them.
    void pass_coordinates(const MatX3& x);
    /// PcgLagged with the off-tick refactorization above.
    LinearSolveResult lagged_solve(const solve::SparseMatrix& A, const VecX& b, VecX& x);
    /// Implicit Euler, K_R new this step: A = cK K_R + cM M, f_int and m_tmp =
    /// K_R v_r straight from the model's kernels (Model::assemble_step); false where the model
    /// cannot (then nothing changed).
    bool assemble_step_matrix(const State& s, double cK, double cM, StepReport& report);

    elasticity::Model* m_model;
    MatX3 m_rest; ///< the model's rest rows, refreshed with the topology
    IntegratorOptions m_options;
    LinearSolver m_solver;
    // PcgLagged only: the factor-preconditioned PCG (never refactors by itself), the block
    // Jacobi bridge, the worker, and the hand-over schedule.
    std::unique_ptr<solve::PcgSolver> m_lagged, m_bridge;
    std::unique_ptr<solve::BackgroundCholesky> m_factor_job;
    bool m_has_factor = false; ///< m_lagged holds a factor of the current pattern
    bool m_pattern_changed = false; ///< a new pattern waits for its background factor
    int m_handover_in = -1; ///< solves until the background factor is installed (-1: none)
    bool m_job_for_new_pattern = false; ///< the running job replaces a wrong-pattern factor
    int m_solves_since_factor = 0;
    LaggedStatus m_lagged_status;
    VecX m_fext; ///< full (3#N)
    std::vector<NodeSpring> m_springs;
    VecX m_spring_diag; ///< reduced spring stiffness (#free) [N/m]
    VecX m_spring_in_A; ///< what the springs currently add to m_A's diagonal (#free, or empty)
    /// Reduced spring forces at x into m_spring_f, their stiffness into m_spring_diag.
    void springs_reduced(const MatX3& x);
    VecX m_spring_f;
    PenaltyField* m_penalty = nullptr;
    PenaltySet m_penalty_set;
    /// What the penalty blocks currently add to m_A's values (undone before the next step's).
    std::vector<std::pair<Index, double>> m_penalty_in_A, m_penalty_scratch;
    std::vector<Mat3> m_node_blocks; ///< semi-implicit: per-node penalty blocks
    /// Evaluates the penalty field for a step of h from x, v; false when no point is active.
    bool evaluate_penalty(const MatX3& x, const MatX3& v, double h, StepReport& report);
    /// Static: the penalty force at s.x into m_rhs and its stiffness into the tangent m_K.
    void static_penalty(const State& s, StepReport& report);
    /// Semi-implicit Euler with penalty points: m_v_r <- the new velocity, each node solving
    /// its own 3x3 system (M + h^2 K_s + h^2 K_node + h D_node) dv = h (f + f_s + f_c - ...).
    void semi_implicit_penalty_velocity(const State& s, double h, const VecX& M);
    std::uint64_t m_topology = ~std::uint64_t(0);
    std::vector<Index> m_dof_map_then; ///< the model's dof map at m_topology
    /// prepare(): the positions its assembly (m_K, f_int) was made at, for the next step
    /// (empty: none), and the model's cell version then
    MatX3 m_prepared_x;
    std::uint64_t m_prepared_cells = 0;
    /// prepare() made A and K v directly (assemble_step_matrix), at the velocities m_prepared_v
    /// and for the step size m_prepared_h [s]
    bool m_prepared_direct = false;
    MatX3 m_prepared_v;
    double m_prepared_h = 0;
    double m_divergence_limit = 0;
    // Work arrays, reused between steps.
    solve::SparseMatrix m_K, m_A;
    /// The model's pattern changed since m_K last took it (assemble() renews it first).
    bool m_K_pattern_stale = true;
    MatX3 m_v_masked; ///< assemble_step_matrix(): the velocities with fixed DOFs zeroed
    VecX m_fint, m_fint_r, m_fext_r, m_v_r, m_rhs, m_dv, m_tmp, m_full, m_coords, m_shift;
    /// ImplicitEuler with stiffness_every > 1: steps since K_R (and A) were last assembled
    /// (-1: none valid for the current pattern)
    int m_stiffness_age = -1;
    std::uint64_t m_stiffness_cells = 0; ///< model cell_version() of the assembled K_R
    int m_turn = 0; ///< the cells' turn of Model::assemble_in_turns (stiffness_every > 1)
    VecX
        m_dv_prev; ///< the velocity increment of the step before the last (extrapolated warm start)
    State m_backup;
    std::vector<State> m_guard_start; ///< energy_guard: the state before each halving level
    /// energy_guard: kinetic + elastic energy [J] of the last state the guard evaluated, with
    /// that state and the model versions, so the next step's start (the same state unless
    /// something moved it) costs no second evaluation.
    struct GuardCache {
        MatX3 x, v;
        std::uint64_t cell_version = 0, topology_version = 0;
        double energy = 0;
        bool valid = false;
    };
    mutable GuardCache m_guard_cache;
    /// Squared stretch per cell of the current state, valid for model cell_version()
    /// m_stretch_cells (the explosion test compares each cell with itself before the step).
    std::vector<double> m_stretch2, m_stretch2_new;
    std::uint64_t m_stretch_cells = ~std::uint64_t(0);
};

} // namespace polycut::integrate
