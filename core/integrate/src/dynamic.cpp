// Dynamic steps on the reduced (free-DOF) system.
#include "impl.hpp"

#include "polycut/common/stats.hpp"

namespace polycut::integrate {

// Backward Euler linearized once per step (DESIGN.md sec. 4; 000 sec. 3.6):
//   (M + h D + h^2 K_R) dv = h (f_ext + f_int(x) - (D + h K_R) v),  D = alpha M + beta K_R,
//   v += dv,  x += h v.
void Integrator::Impl::implicit_euler(State& s, StepReport& r)
{
    const double h = options.dt;
    const double alpha = model.material().rayleigh_mass;
    const double beta = model.material().rayleigh_stiffness;
    Stopwatch watch;
    model.assemble(s.x, mode(), &K, &f_int);
    f_total += f_int;
    model.reduce(f_total, f_red);
    model.reduce(flat(s.v), v_red);
    const VecX& m = model.reduced_mass();
    Kv.noalias() = K * v_red;
    rhs = h * (f_red - alpha * m.cwiseProduct(v_red) - (beta + h) * Kv);
    // A = (1 + h alpha) M + (h beta + h^2) K, on K's pattern.
    const double ks = h * beta + h * h;
    const Index nnz = Index(K.nonZeros());
    double* a = A.valuePtr();
    const double* k = K.valuePtr();
    for (Index i = 0; i < nnz; ++i)
        a[i] = ks * k[i];
    const auto& diag = model.diagonal_slots();
    for (Index i = 0; i < Index(diag.size()); ++i)
        a[diag[std::size_t(i)]] += (1.0 + h * alpha) * m[i];
    r.assembly_ms = watch.ms();
    watch.restart();
    if (dv.size() != rhs.size())
        dv = VecX::Zero(rhs.size());
    const detail::LinearResult lr = system.solve(A, rhs, dv, true);
    r.solve_ms = watch.ms();
    r.solver_iterations = lr.iterations;
    r.residual = lr.relative_residual;
    r.status = lr.status;
    r.refactored = lr.refactored;
    if (lr.status != solve::SolveStatus::Ok && lr.status != solve::SolveStatus::NotConverged)
        return;
    v_red += dv;
    VecX v_full = VecX::Zero(3 * model.num_nodes());
    model.expand(v_red, v_full);
    flat(s.v) = v_full;
    flat(s.x) += h * v_full;
}

// Semi-implicit (symplectic) Euler (001 sec. 6, 003 sec. 6): v += h M^-1 (f - D v), x += h v.
// Explicit in the forces: stable only below the element's CFL-like limit; divergence is caught
// and rolled back by step().
void Integrator::Impl::semi_implicit_euler(State& s, StepReport& r)
{
    const double h = options.dt;
    const double alpha = model.material().rayleigh_mass;
    const double beta = model.material().rayleigh_stiffness;
    Stopwatch watch;
    model.assemble(s.x, mode(), beta > 0 ? &K : nullptr, &f_int);
    f_total += f_int;
    model.reduce(f_total, f_red);
    model.reduce(flat(s.v), v_red);
    const VecX& m = model.reduced_mass();
    if (beta > 0)
        Kv.noalias() = K * v_red;
    else
        Kv = VecX::Zero(v_red.size());
    for (Index i = 0; i < v_red.size(); ++i)
        if (m[i] > 0)
            v_red[i] += h * (f_red[i] - alpha * m[i] * v_red[i] - beta * Kv[i]) / m[i];
    r.assembly_ms = watch.ms();
    VecX v_full = VecX::Zero(3 * model.num_nodes());
    model.expand(v_red, v_full);
    flat(s.v) = v_full;
    flat(s.x) += h * v_full;
}

} // namespace polycut::integrate
