// Private state of the Integrator, shared by its source files.
#pragma once

#include "linear_system.hpp"
#include "polycut/integrate/integrator.hpp"

namespace polycut::integrate {

struct Integrator::Impl {
    elasticity::ElasticModel& model;
    IntegratorOptions options;
    detail::LinearSystem system;
    std::uint64_t seen_topology = ~std::uint64_t(0);
    solve::SparseMatrix K; ///< reduced stiffness (corotated or linear)
    solve::SparseMatrix A; ///< reduced system matrix of the dynamic step
    solve::SparseMatrix K0; ///< static fixed-point: rest stiffness
    bool K0_factored = false;
    VecX f_int, f_total, f_red, rhs, dv, v_red, Kv, x_flat_backup, v_flat_backup, dx_full;
    double mesh_size = 1; ///< rest bounding-box diagonal [m]

    Impl(elasticity::ElasticModel& m, IntegratorOptions o);
    /// Rebuilds matrices and work vectors after a topology change.
    void prepare();
    /// External + gravity forces (3#N) [N] into f_total.
    void total_external(const VecX& f_ext, const Vec3& gravity);
    elasticity::ForceMode mode() const
    {
        return options.corotated ? elasticity::ForceMode::Corotated : elasticity::ForceMode::Linear;
    }
    void implicit_euler(State& s, StepReport& r);
    void semi_implicit_euler(State& s, StepReport& r);
    void static_solve(State& s, StepReport& r);
};

} // namespace polycut::integrate
