// Steps an ElasticModel in time or to equilibrium (DESIGN.md sec. 4). A step never throws: on a
// non-finite value, a solver failure or divergence it restores the state it started from and
// says why in the StepReport (MuJoCo-style warnings, STYLE.md).
#pragma once

#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/integrate/linear_solver.hpp"
#include "polycut/integrate/options.hpp"

namespace polycut::integrate {

/// Integrator over a model it does not own (the model must outlive it).
class Integrator {
public:
    Integrator(elasticity::ElasticModel& model, const IntegratorOptions& options);

    const IntegratorOptions& options() const { return m_options; }
    /// The rest state: x = X, v = 0, time 0.
    State rest_state() const;
    /// External nodal forces (3#N) [N], applied in addition to gravity; an empty vector means
    /// none. Forces on fixed DOFs are ignored.
    void set_external_forces(VecX f_ext);
    /// Advances `state` by one step (dt; Static: to equilibrium). Never throws.
    StepReport step(State& state);
    /// Total energy [J]: kinetic 1/2 v^T M v + elastic (force mode of the options).
    double energy(const State& state) const;

private:
    void ensure_topology(StepReport& report);
    bool step_implicit(State& s, StepReport& report);
    bool step_semi_implicit(State& s, StepReport& report);
    bool step_static(State& s, StepReport& report);
    /// Reduced f_ext + gravity (#free), into m_fext_r.
    void external_reduced();
    double assemble(const MatX3& x, elasticity::ForceMode mode, bool with_K, StepReport& report);
    bool linear_solve(const solve::SparseMatrix& A, const VecX& b, VecX& x, StepReport& report);

    elasticity::ElasticModel* m_model;
    IntegratorOptions m_options;
    LinearSolver m_solver;
    VecX m_fext; ///< full (3#N)
    std::uint64_t m_topology = ~std::uint64_t(0);
    double m_divergence_limit = 0;
    // Work arrays, reused between steps.
    solve::SparseMatrix m_K, m_A;
    VecX m_fint, m_fint_r, m_fext_r, m_v_r, m_rhs, m_dv, m_tmp, m_full;
    VecX
        m_dv_prev; ///< the velocity increment of the step before the last (extrapolated warm start)
    State m_backup;
};

} // namespace polycut::integrate
