// Matrix-free CG with fixed nodes (002 sec. 3.1): the residual r = f - K u is zeroed at fixed
// DOFs; since every search direction d is a combination of such residuals, d is zero there too
// and the fixed displacements never change. The fixed DOFs are in equilibrium by construction:
// the constraint forces balance whatever K u gives there.
#include "polycut/solve/cg_relaxation.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <string>

namespace polycut::solve {
namespace {

void zero_fixed(const std::vector<bool>& fixed, Vector& v) {
    for (long i = 0; i < v.size(); ++i)
        if (fixed[static_cast<size_t>(i)])
            v[i] = 0;
}

} // namespace

RelaxationResult CgRelaxation::relax(const StiffnessProduct& apply_K, const Vector& f_ext,
    const std::vector<bool>& fixed_dof, Vector& u, double tol, int max_iterations) {
    const long n = f_ext.size();
    if (static_cast<long>(fixed_dof.size()) != n || u.size() != n)
        throw InputError("cg_relax",
            "sizes differ: f_ext " + std::to_string(n) + ", fixed_dof "
                + std::to_string(fixed_dof.size()) + ", u " + std::to_string(u.size()));
    RelaxationResult result;
    m_r.resize(n);
    m_d.resize(n);
    m_q.resize(n);

    // reference: ||f_ext|| on the free DOFs (forces on fixed DOFs go into the supports)
    m_d = f_ext;
    zero_fixed(fixed_dof, m_d);
    double reference = m_d.norm();

    // r' = -K u; r = r' + f zeroed at fixed DOFs (002 sec. 3.1)
    apply_K(u, m_q);
    m_r = f_ext - m_q;
    zero_fixed(fixed_dof, m_r);
    double rr = m_r.squaredNorm();
    if (!std::isfinite(rr))
        return result;
    if (reference == 0)
        reference = std::sqrt(rr);
    if (reference == 0) {
        result.converged = true;
        return result;
    }
    const double target = tol * reference;
    m_d = m_r;
    while (std::sqrt(rr) >= target && result.iterations < max_iterations) {
        apply_K(m_d, m_q);
        zero_fixed(fixed_dof, m_q);
        const double dq = m_d.dot(m_q);
        if (!(dq > 0)) {
            result.breakdown = true;
            break;
        }
        const double alpha = rr / dq;
        u += alpha * m_d;
        m_r -= alpha * m_q;
        const double rr_new = m_r.squaredNorm();
        ++result.iterations;
        if (!std::isfinite(rr_new))
            break;
        m_d = m_r + (rr_new / rr) * m_d;
        rr = rr_new;
    }
    // true residual, not the recursively updated one
    apply_K(u, m_q);
    m_r = f_ext - m_q;
    zero_fixed(fixed_dof, m_r);
    const double r_norm = m_r.norm();
    result.relative_residual = r_norm / reference;
    result.converged = std::isfinite(r_norm) && !result.breakdown && std::sqrt(rr) < target;
    return result;
}

RelaxationResult cg_relax(const StiffnessProduct& apply_K, const Vector& f_ext,
    const std::vector<bool>& fixed_dof, Vector& u, double tol, int max_iterations) {
    CgRelaxation relaxation;
    return relaxation.relax(apply_K, f_ext, fixed_dof, u, tol, max_iterations);
}

} // namespace polycut::solve
