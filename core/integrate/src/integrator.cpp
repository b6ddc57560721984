#include "polycut/integrate/integrator.hpp"

#include "polycut/common/stats.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <exception>

namespace polycut::integrate {

using elasticity::ForceMode;

namespace {
SolverOptions with_threads(SolverOptions s, int threads) {
    s.threads = std::max(threads, 1);
    return s;
}
} // namespace

Integrator::Integrator(elasticity::Model& model, const IntegratorOptions& options)
    : m_model(&model)
    , m_options(options)
    , m_solver(with_threads(options.solver, options.threads)) {
    model.set_threads(std::max(options.threads, 1));
    if (options.solver.kind == LinearSolverKind::PcgLagged) {
        // The factor-preconditioned PCG never refactors on its own schedule (lagged_solve()
        // does, off the tick); it only factors in the foreground on the very first solve and
        // when a stale factor cannot reach the tolerance.
        solve::PcgOptions p;
        p.relative_tolerance = options.solver.relative_tolerance;
        p.max_iterations = options.solver.max_iterations;
        p.preconditioner = solve::Preconditioner::LaggedCholesky;
        p.refactor_every = 0;
        p.refactor_iterations = INT_MAX;
        p.background_refactor = false;
        p.iteration_budget = options.solver.iteration_budget;
        p.threads = std::max(options.threads, 1);
        m_lagged = std::make_unique<solve::PcgSolver>(p);
        p.preconditioner = solve::Preconditioner::BlockJacobi3;
        m_bridge = std::make_unique<solve::PcgSolver>(p);
        m_factor_job = std::make_unique<solve::BackgroundCholesky>();
    }
}

int Integrator::handover_solves(Index n) {
    // CHOLMOD factors a 6.6k-DOF tet system in ~45 ms and a 24k one in ~420 ms on one core here
    // (docs/perf.md), roughly (n / 6000)^1.5 x 40 ms: allow ~4x that at 60 Hz, at least 2 solves.
    const double ticks = 4.0 * std::pow(std::max(double(n), 0.0) / 6000.0, 1.5) * 40.0 / 16.7;
    return std::clamp(int(std::ceil(ticks)), 2, 10000);
}

LinearSolveResult Integrator::lagged_solve(const solve::SparseMatrix& A, const VecX& b, VecX& x) {
    LinearSolveResult r;
    if (A.rows() == 0) {
        x.resize(0);
        return r;
    }
    LaggedStatus& st = m_lagged_status;
    auto start_job = [&] {
        m_factor_job->start(solve::SparseMatrix(A)); // a copy: A changes next step
        m_handover_in = handover_solves(Index(A.rows()));
        m_solves_since_factor = 0;
        ++st.background_factorizations;
        st.pending = true;
    };
    bool installed = false;
    if (m_handover_in == 0) {
        // The background factor's fixed hand-over: wait for it if it is late (deterministic).
        if (!m_factor_job->ready())
            ++st.waits;
        m_factor_job->wait();
        std::optional<solve::CholmodSolver> factor = m_factor_job->take();
        if (factor && factor->size() == A.rows()) {
            m_lagged->set_preconditioner_factor(std::move(*factor));
            m_has_factor = true;
            installed = true;
        }
        // On failure the lagged PCG factors in the foreground and reports the status.
        m_pattern_changed = false;
        m_handover_in = -1;
        m_solves_since_factor = 0;
        st.pending = false;
    }
    if (m_pattern_changed && m_handover_in < 0)
        start_job();
    solve::PcgResult p;
    if (m_pattern_changed) {
        // The old factor has the old pattern (and size): block Jacobi carries the solves.
        p = m_bridge->solve(A, b, x);
        ++st.bridged_solves;
        --m_handover_in;
    } else {
        p = m_lagged->solve(A, b, x);
        if (p.refactored && !installed) {
            ++st.foreground_factorizations;
            m_solves_since_factor = 0;
        }
        m_has_factor = true;
        ++m_solves_since_factor;
        if (m_handover_in > 0) {
            --m_handover_in; // a refresh is under way; the old factor carries this solve
        } else if (p.status == solve::SolveStatus::Ok
            && ((m_options.solver.refactor_every > 0
                    && m_solves_since_factor >= m_options.solver.refactor_every)
                || p.iterations > m_options.solver.refactor_iterations)) {
            start_job();
        }
    }
    r.status = p.status;
    r.iterations = p.iterations;
    r.relative_residual = p.relative_residual;
    r.budget_reached = p.budget_reached;
    return r;
}

State Integrator::rest_state() const {
    State s;
    m_model->rest_rows(s.x);
    s.v.setZero(s.x.rows(), 3);
    return s;
}

void Integrator::set_external_forces(VecX f_ext) {
    m_fext = std::move(f_ext);
}

void Integrator::set_springs(std::vector<NodeSpring> springs) {
    m_springs = std::move(springs);
}

void Integrator::springs_reduced(const MatX3& x) {
    const Index n_free = m_model->num_free_dofs();
    m_spring_f.setZero(n_free);
    add_spring_forces(m_springs, x, m_model->dof_map(), m_spring_f);
    spring_diagonal(m_springs, m_model->dof_map(), n_free, m_spring_diag);
}

void Integrator::external_reduced() {
    const Index n = m_model->num_rows();
    m_full.setZero(3 * n);
    if (m_fext.size() == 3 * n)
        m_full = m_fext;
    m_model->add_gravity(m_options.gravity, m_full);
    m_model->reduce(m_full, m_fext_r);
}

double Integrator::assemble(const MatX3& x, ForceMode mode, bool with_K, StepReport& report) {
    const Stopwatch sw;
    if (with_K && m_K_pattern_stale) {
        m_model->pattern_into(m_K);
        m_K_pattern_stale = false;
    }
    m_model->assemble(x, mode, with_K ? &m_K : nullptr, &m_fint);
    m_model->reduce(m_fint, m_fint_r);
    const double ms = sw.ms();
    report.assembly_ms += ms;
    return ms;
}

bool Integrator::linear_solve(
    const solve::SparseMatrix& A, const VecX& b, VecX& x, StepReport& report) {
    const Stopwatch sw;
    const LinearSolveResult r = m_lagged ? lagged_solve(A, b, x) : m_solver.solve(A, b, x);
    report.solve_ms += sw.ms();
    report.solver_iterations += r.iterations;
    report.residual = r.relative_residual;
    report.solver_budget_reached = report.solver_budget_reached || r.budget_reached;
    report.status = r.status;
    if (!r.warning.empty())
        report.warnings.push_back(r.warning);
    if (r.status != solve::SolveStatus::Ok) {
        report.warnings.push_back(
            std::string("linear solve failed: ") + solve::to_string(r.status));
        return false;
    }
    if (!x.allFinite()) {
        report.status = solve::SolveStatus::NonFinite;
        report.warnings.emplace_back("linear solve returned non-finite values");
        return false;
    }
    return true;
}

void Integrator::gather_free(const MatX3& full, VecX& reduced) const {
    // ElasticModel::reduce() without the temporary full vector
    const std::vector<Index>& dof_map = m_model->dof_map();
    const auto f = flat(full);
    reduced.resize(m_model->num_free_dofs());
    for (std::size_t k = 0; k < dof_map.size(); ++k)
        if (dof_map[k] != kNone)
            reduced(dof_map[k]) = f(Index(k));
}

void Integrator::pass_coordinates(const MatX3& x) {
    if (!m_solver.wants_coordinates() || !m_model->rows_are_points())
        return;
    gather_free(x, m_coords);
    m_solver.set_coordinates(m_coords);
}

namespace {
/// x_free += h v_free and v = v_r on free DOFs, v = 0 on fixed DOFs.
void advance(const std::vector<Index>& dof_map, const VecX& v_r, double h, State& s) {
    auto x = flat(s.x);
    auto v = flat(s.v);
    for (std::size_t k = 0; k < dof_map.size(); ++k) {
        const Index r = dof_map[k];
        if (r == kNone) {
            v(Index(k)) = 0;
            continue;
        }
        v(Index(k)) = v_r(r);
        x(Index(k)) += h * v_r(r);
    }
}
} // namespace

bool Integrator::step_implicit(State& s, StepReport& report, double h) {
    // (M + h D + h^2 K_R) dv = h (f_ext + f_int(x) - (D + h K_R) v), D = alpha M + beta K_R.
    const double alpha = m_model->material().rayleigh_mass;
    const double beta = m_model->material().rayleigh_stiffness;
    external_reduced();
    // K_R and A are reused for stiffness_every - 1 steps (options.hpp); forces are always new.
    // A model that can re-linearizes a 1/stiffness_every share of its cells at every step
    // instead (Model::assemble_in_turns): the same lag, without a step that re-assembles all.
    const int period = std::max(m_options.stiffness_every, 1);
    const bool same_cells = m_stiffness_cells == m_model->cell_version();
    bool turned = false;
    if (period > 1 && m_stiffness_age >= 0 && same_cells
        && m_options.force_mode == ForceMode::Corotated) {
        const Stopwatch sw;
        turned = m_model->assemble_in_turns(s.x, m_K, m_fint, m_turn, period);
        if (turned) {
            m_model->reduce(m_fint, m_fint_r);
            report.assembly_ms += sw.ms();
            m_turn = (m_turn + 1) % period;
        }
    }
    const bool new_stiffness
        = !turned && (m_stiffness_age < 0 || m_stiffness_age + 1 >= period || !same_cells);
    const VecX& M = m_model->reduced_mass();
    const double cK = h * beta + h * h, cM = 1.0 + h * alpha;
    // K_R every step (period 1): the kernels write cK K_R into A and sum cK K_R v as they go,
    // so no pass over K forms A (Model::assemble_step); K itself is not kept.
    const bool direct_wanted = new_stiffness && period == 1 && cK > 0;
    // prepare() assembled at these positions already (K, f_int; or A and K v, which also hold
    // its step size and velocities): take that
    const bool prepared = new_stiffness && m_prepared_x.rows() == s.x.rows()
        && m_prepared_cells == m_model->cell_version() && m_prepared_x == s.x
        && (!m_prepared_direct || (direct_wanted && h == m_prepared_h && m_prepared_v == s.v));
    m_prepared_x.resize(0, 3);
    const bool direct
        = prepared ? m_prepared_direct : direct_wanted && assemble_step_matrix(s, cK, cM, report);
    if (!prepared && !turned && !direct)
        assemble(s.x, m_options.force_mode, new_stiffness, report);
    gather_free(s.v, m_v_r);
    if (direct) {
        m_stiffness_age = 0;
        m_stiffness_cells = m_model->cell_version();
        m_spring_in_A.resize(0);
        m_penalty_in_A.clear();
    } else if (new_stiffness || turned) {
        // A = cK K + cM M and K v in one pass over K
        m_shift = cM * M;
        solve::scale_shift_multiply(m_K, cK, m_shift, m_v_r, m_A, m_tmp, m_model->threads());
        m_stiffness_age = 0;
        m_stiffness_cells = m_model->cell_version();
        m_spring_in_A.resize(0);
        m_penalty_in_A.clear(); // A was rewritten: the last step's penalty blocks are gone
    } else {
        solve::multiply_symmetric(m_K, m_v_r, m_tmp, m_model->threads());
        ++m_stiffness_age;
    }
    m_rhs = h * (m_fext_r + m_fint_r - alpha * M.cwiseProduct(m_v_r) - (beta + h) * m_tmp);
    // Springs (diagonal stiffness K_s, undamped): + h^2 K_s in A, h (f_s(x) - h K_s v) in the
    // right-hand side. A reused from an earlier step gets the change of h^2 K_s since then.
    springs_reduced(s.x);
    m_rhs += h * (m_spring_f - h * m_spring_diag.cwiseProduct(m_v_r));
    if (m_spring_in_A.size() != m_spring_diag.size())
        m_spring_in_A.setZero(m_spring_diag.size());
    add_to_diagonal(m_A, h * h * m_spring_diag - m_spring_in_A);
    m_spring_in_A = h * h * m_spring_diag;
    // Penalty points linearized at x: f(x_{n+1}) ~ f0 - K h (v + dv), f(v_{n+1}) = -D (v + dv -
    // v_other), so + h^2 K + h D in A and h (f0 - h K v - D (v - v_other)) on the right
    // (penalty.hpp).
    undo_penalty_blocks(m_A, m_penalty_in_A);
    if (evaluate_penalty(s.x, s.v, h, report)) {
        add_penalty_forces(m_penalty_set, &s.v, h, m_model->dof_map(), h, m_rhs);
        report.penalty_entries_dropped += int(
            add_penalty_blocks(m_penalty_set, m_model->dof_map(), h * h, h, m_A, m_penalty_in_A));
    }
    if (!m_rhs.allFinite()) {
        report.status = solve::SolveStatus::NonFinite;
        report.warnings.emplace_back("non-finite force or velocity");
        return false;
    }
    // m_dv holds the previous step's dv: the warm start (or extrapolated from the last two).
    const bool extrapolate = m_options.extrapolate_warm_start && m_dv_prev.size() == m_dv.size();
    if (m_options.extrapolate_warm_start) {
        m_tmp = m_dv; // dv_{n-1}
        if (extrapolate)
            m_dv = 2.0 * m_tmp - m_dv_prev;
    }
    pass_coordinates(s.x);
    m_solver.set_absolute_tolerance(m_options.solver.load_tolerance * h * m_fext_r.norm());
    if (!linear_solve(m_A, m_rhs, m_dv, report))
        return false;
    if (m_options.extrapolate_warm_start)
        m_dv_prev = m_tmp;
    m_v_r += m_dv;
    advance(m_model->dof_map(), m_v_r, h, s);
    return true;
}

bool Integrator::step_semi_implicit(State& s, StepReport& report) {
    // v <- v + h M^-1 (f_ext + f_int(x) - D v), x <- x + h v (001, 003).
    const double h = m_options.dt;
    const double alpha = m_model->material().rayleigh_mass;
    const double beta = m_model->material().rayleigh_stiffness;
    const VecX& M = m_model->reduced_mass();
    if (M.size() > 0 && !(M.minCoeff() > 0)) {
        report.warnings.emplace_back("semi-implicit Euler needs a positive mass at every free DOF");
        return false;
    }
    external_reduced();
    assemble(s.x, m_options.force_mode, beta > 0, report);
    gather_free(s.v, m_v_r);
    m_rhs = m_fext_r + m_fint_r - alpha * M.cwiseProduct(m_v_r);
    if (beta > 0) {
        m_tmp.noalias() = m_K * m_v_r;
        m_rhs -= beta * m_tmp;
    }
    if (!m_rhs.allFinite()) {
        report.status = solve::SolveStatus::NonFinite;
        report.warnings.emplace_back("non-finite force or velocity");
        return false;
    }
    // Springs per DOF, implicit in the new velocity (their stiffness is diagonal):
    // (M + h^2 K_s) v' = M v + h (f + f_s(x)).
    springs_reduced(s.x);
    if (evaluate_penalty(s.x, s.v, h, report))
        semi_implicit_penalty_velocity(s, h, M);
    else
        m_v_r = (M.cwiseProduct(m_v_r) + h * (m_rhs + m_spring_f))
                    .cwiseQuotient(M + h * h * m_spring_diag);
    advance(m_model->dof_map(), m_v_r, h, s);
    return true;
}

bool Integrator::step_static(State& s, StepReport& report) {
    external_reduced();
    if (!m_fext_r.allFinite()) {
        report.status = solve::SolveStatus::NonFinite;
        report.warnings.emplace_back("non-finite external force");
        return false;
    }
    const double fnorm = m_fext_r.norm();
    const std::vector<Index>& dof_map = m_model->dof_map();
    auto apply = [&](const VecX& dx, double step) {
        auto x = flat(s.x);
        for (std::size_t k = 0; k < dof_map.size(); ++k)
            if (dof_map[k] != kNone)
                x(Index(k)) += step * dx(dof_map[k]);
    };
    if (m_options.static_mode == StaticMode::Linear) {
        assemble(s.x, ForceMode::Linear, true, report);
        springs_reduced(s.x);
        add_to_diagonal(m_K, m_spring_diag);
        m_rhs = m_fext_r + m_fint_r + m_spring_f;
        static_penalty(s, report);
        m_dv.setZero(m_rhs.size());
        pass_coordinates(s.x);
        if (!linear_solve(m_K, m_rhs, m_dv, report))
            return false;
        apply(m_dv, 1.0);
        report.newton_iterations = 1;
        s.v.setZero();
        return true;
    }
    double reference = fnorm;
    double equilibrium = 0;
    bool converged = false;
    for (int it = 0; it < m_options.static_max_iterations; ++it) {
        assemble(s.x, ForceMode::Corotated, true, report);
        springs_reduced(s.x);
        add_to_diagonal(m_K, m_spring_diag);
        m_rhs = m_fext_r + m_fint_r + m_spring_f;
        static_penalty(s, report);
        double rn = m_rhs.norm();
        if (it == 0)
            reference = std::max(fnorm, rn);
        equilibrium = reference > 0 ? rn / reference : 0.0;
        if (!std::isfinite(rn)) {
            report.status = solve::SolveStatus::NonFinite;
            report.warnings.emplace_back("non-finite residual");
            return false;
        }
        if (rn <= m_options.static_tolerance * reference) {
            converged = true;
            break;
        }
        ++report.newton_iterations;
        m_dv.setZero(m_rhs.size());
        pass_coordinates(s.x);
        if (!linear_solve(m_K, m_rhs, m_dv, report))
            return false;
        if (m_options.static_mode == StaticMode::CorotatedFixedPoint) {
            apply(m_dv, 1.0);
            continue;
        }
        // Backtracking on the total potential energy Pi = E_el(x) - f_ext . x: the K_R step is
        // a descent direction for it (K_R is SPD and r ~ -grad Pi), whereas the residual norm
        // may rise on the way to the solution when cells rotate.
        auto potential = [&]() {
            double work = 0;
            const auto x = flat(s.x);
            for (std::size_t k = 0; k < dof_map.size(); ++k)
                if (dof_map[k] != kNone)
                    work += m_fext_r(dof_map[k]) * x(Index(k));
            return m_model->elastic_energy(s.x, ForceMode::Corotated) - work
                + spring_energy(m_springs, s.x) + (m_penalty ? m_penalty->energy(s.x) : 0.0);
        };
        const double pi0 = potential();
        double step = 1.0;
        for (int k = 0; k < 10; ++k) {
            apply(m_dv, step);
            // Near the solution Pi changes at O(|r|^2), below its round-off: accept a step that
            // does not raise Pi beyond round-off or that lowers the residual.
            if (potential() <= pi0 + 1e-12 * std::abs(pi0) || k == 9)
                break;
            assemble(s.x, ForceMode::Corotated, false, report);
            springs_reduced(s.x);
            m_tmp = m_fext_r + m_fint_r + m_spring_f;
            if (evaluate_penalty(s.x, s.v, 0.0, report))
                add_penalty_forces(m_penalty_set, nullptr, 0.0, m_model->dof_map(), 1.0, m_tmp);
            if (m_tmp.norm() < rn)
                break;
            apply(m_dv, -step);
            step *= 0.5;
        }
    }
    report.residual = equilibrium;
    if (!converged) {
        report.status = solve::SolveStatus::NotConverged;
        report.warnings.push_back("static solve did not reach the tolerance in "
            + std::to_string(m_options.static_max_iterations) + " iterations");
    } else {
        report.status = solve::SolveStatus::Ok;
    }
    s.v.setZero();
    return true;
}

StepReport Integrator::step(State& s) {
    const Stopwatch sw;
    StepReport report;
    bool backed_up = false;
    try {
        ensure_topology(report);
        // the assembly runs on the solver's threads: one while a background set-up runs
        // (solve::AmgOptions::background_serial)
        m_model->set_threads(std::max(1, std::min(m_options.threads, m_solver.threads())));
        const Index n = m_model->num_rows();
        if (s.x.rows() != n) {
            report.warnings.emplace_back("state has the wrong number of nodes");
            report.rolled_back = true;
            report.step_ms = sw.ms();
            return report;
        }
        if (s.v.rows() != n)
            s.v.setZero(n, 3);
        m_backup.x = s.x;
        m_backup.v = s.v;
        m_backup.time = s.time;
        backed_up = true;
        bool ok = s.x.allFinite() && s.v.allFinite();
        if (!ok)
            report.warnings.emplace_back("non-finite state before the step");
        if (ok) {
            switch (m_options.kind) {
            case IntegratorKind::Static:
                ok = step_static(s, report);
                break;
            case IntegratorKind::ImplicitEuler:
                ok = m_options.energy_guard ? step_implicit_guarded(s, report, m_options.dt, 0)
                                            : step_implicit(s, report, m_options.dt);
                break;
            case IntegratorKind::SemiImplicitEuler:
                ok = step_semi_implicit(s, report);
                break;
            }
        }
        if (ok && !(s.x.allFinite() && s.v.allFinite())) {
            ok = false;
            report.status = solve::SolveStatus::NonFinite;
            report.warnings.emplace_back("non-finite state after the step");
        }
        if (ok) {
            double worst = 0;
            for (Index i = 0; i < n; ++i)
                worst = std::max(worst, (s.x.row(i) - m_rest.row(i)).norm());
            if (worst > m_divergence_limit) {
                ok = false;
                report.warnings.emplace_back("diverged: displacement beyond the divergence limit");
            }
        }
        if (ok) {
            m_model->cell_stretch_squared(s.x, m_stretch2_new);
            // Exploded: a cell stretched past the limit that also grew more than stretch_growth
            // times in this step (per cell). Slow, large stretch is the model's answer.
            if (m_stretch_cells != m_model->cell_version()
                || m_stretch2.size() != m_stretch2_new.size()) {
                m_model->cell_stretch_squared(m_backup.x, m_stretch2);
                m_stretch_cells = m_model->cell_version();
            }
            const double limit2 = m_options.stretch_limit * m_options.stretch_limit;
            const double growth2 = m_options.stretch_growth * m_options.stretch_growth;
            double worst2 = 0, before2 = 1;
            for (std::size_t c = 0; c < m_stretch2_new.size(); ++c) {
                const double now2 = m_stretch2_new[c]; // +inf for non-finite positions
                const bool exploded = !(now2 <= limit2) && !(now2 <= growth2 * m_stretch2[c]);
                if (exploded && !(now2 <= worst2)) {
                    worst2 = now2;
                    before2 = m_stretch2[c];
                }
            }
            if (worst2 > 0) {
                ok = false;
                report.warnings.push_back("exploded: a cell stretched "
                    + std::to_string(std::sqrt(worst2)) + " times its rest size (limit "
                    + std::to_string(m_options.stretch_limit) + "), "
                    + std::to_string(std::sqrt(worst2 / before2))
                    + " times its stretch before the step");
            } else
                std::swap(m_stretch2, m_stretch2_new);
        }
        if (ok) {
            if (m_options.kind != IntegratorKind::Static)
                s.time += m_options.dt;
        } else {
            s.x = m_backup.x;
            s.v = m_backup.v;
            s.time = m_backup.time;
            report.rolled_back = true;
            m_dv.setZero(m_model->num_free_dofs()); // a bad warm start must not persist
            m_dv_prev.resize(0);
            m_solver.forget_solutions();
            m_stiffness_age = -1; // nor a stiffness from the failed step
        }
    } catch (const std::exception& e) {
        report.warnings.push_back(std::string("step failed: ") + e.what());
        if (backed_up) {
            s.x = m_backup.x;
            s.v = m_backup.v;
            s.time = m_backup.time;
        }
        m_solver.forget_solutions();
        report.rolled_back = true;
    }
    report.step_ms = sw.ms();
    return report;
}

double Integrator::max_cell_stretch(const MatX3& x) const {
    // Per cell, the largest distance from its first node to another node, deformed over rest:
    // 1 under rigid motion, growing without bound in an exploding step. Measured against the
    // cell's extent rather than per node pair, so nodes a cut left close together do not make
    // tiny, harmless motions look like stretch. The model caches the rest extents and splits
    // the cells over its threads.
    return m_model->max_cell_stretch(x);
}

double Integrator::energy(const State& s) const {
    const VecX& m = m_model->row_mass();
    double kinetic = 0;
    for (Index i = 0; i < s.v.rows(); ++i)
        kinetic += 0.5 * m(i) * s.v.row(i).squaredNorm();
    return kinetic + m_model->elastic_energy(s.x, m_options.force_mode);
}

} // namespace polycut::integrate
