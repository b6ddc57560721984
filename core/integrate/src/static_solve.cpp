// Static equilibrium f_ext + f_int(x) = 0 on the free DOFs.
#include "impl.hpp"

#include "polycut/common/stats.hpp"
#include "polycut/solve/cg_relaxation.hpp"

namespace polycut::integrate {

// Linear: one solve of K dx = r (repeated once if the residual is still above tolerance).
// Corotated Newton: K_R reassembled each iteration; fixed point: the rest stiffness K_0 (factored
// once) against the corotated residual. For the `tet` method with SolverKind::CgRelaxation each
// solve is the CG relaxation of 002 sec. 3.1 (stop at ||r|| < tol ||f_ext||).
void Integrator::Impl::static_solve(State& s, StepReport& r)
{
    model.reduce(f_total, f_red);
    const double ref = f_red.norm() > 0 ? f_red.norm() : 1.0;
    const bool fixed_point = options.corotated && options.static_mode == StaticMode::FixedPoint;
    solve::CgRelaxation relax;
    Stopwatch watch;
    s.v.setZero();
    for (int it = 0; it < options.static_max_iterations; ++it) {
        watch.restart();
        const bool need_K = !fixed_point || !K0_factored;
        if (fixed_point && !K0_factored) {
            // Rest stiffness: linear assembly at any x gives K_0.
            model.assemble(s.x, elasticity::ForceMode::Linear, &K0, nullptr);
        }
        model.assemble(s.x, mode(), need_K && !fixed_point ? &K : nullptr, &f_int);
        f_total += f_int;
        model.reduce(f_total, rhs);
        f_total -= f_int;
        r.assembly_ms += watch.ms();
        r.residual = rhs.norm() / ref;
        r.newton_iterations = it;
        if (r.residual <= options.static_tolerance)
            return;
        watch.restart();
        const solve::SparseMatrix& Kit = fixed_point ? K0 : K;
        VecX dx = VecX::Zero(rhs.size());
        detail::LinearResult lr;
        if (options.solver == SolverKind::CgRelaxation) {
            const std::vector<bool> none(std::size_t(rhs.size()), false);
            const auto apply = [&](const solve::Vector& d, solve::Vector& Kd) { Kd.noalias() = Kit * d; };
            const double tol = std::min(options.pcg.relative_tolerance, options.static_tolerance);
            const solve::RelaxationResult rr
                = relax.relax(apply, rhs, none, dx, tol, options.pcg.max_iterations);
            lr.iterations = rr.iterations;
            lr.relative_residual = rr.relative_residual;
            lr.status = rr.breakdown ? solve::SolveStatus::NotPositiveDefinite
                : rr.converged         ? solve::SolveStatus::Ok
                                       : solve::SolveStatus::NotConverged;
        } else {
            lr = system.solve(Kit, rhs, dx, fixed_point ? !K0_factored : (options.corotated || it == 0));
        }
        K0_factored = K0_factored || fixed_point;
        r.solve_ms += watch.ms();
        r.solver_iterations += lr.iterations;
        r.refactored = r.refactored || lr.refactored;
        r.status = lr.status;
        if (lr.status != solve::SolveStatus::Ok && lr.status != solve::SolveStatus::NotConverged)
            return;
        VecX dx_full = VecX::Zero(3 * model.num_nodes());
        model.expand(dx, dx_full);
        flat(s.x) += dx_full;
    }
    // Final residual after the last update.
    model.assemble(s.x, mode(), nullptr, &f_int);
    f_total += f_int;
    model.reduce(f_total, rhs);
    f_total -= f_int;
    r.residual = rhs.norm() / ref;
    r.newton_iterations = options.static_max_iterations;
    if (r.residual > options.static_tolerance)
        r.warnings.push_back("static solve stopped at the iteration limit above tolerance");
}

} // namespace polycut::integrate
