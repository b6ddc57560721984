#include "linear_system.hpp"

namespace polycut::integrate::detail {

LinearSystem::LinearSystem(SolverKind kind, const solve::PcgOptions& pcg)
    : m_kind(kind)
    , m_pcg(pcg)
{
}

void LinearSystem::reset()
{
    m_cholmod = solve::CholmodSolver();
    m_pcg.reset();
}

LinearResult LinearSystem::solve(const solve::SparseMatrix& A, const VecX& b, VecX& x,
    bool matrix_changed)
{
    LinearResult r;
    if (m_kind == SolverKind::Cholmod) {
        if (matrix_changed || !m_cholmod.ready() || m_cholmod.size() != A.rows()) {
            r.status = m_cholmod.factorize(A);
            r.refactored = true;
            if (r.status != solve::SolveStatus::Ok)
                return r;
        }
        r.status = m_cholmod.solve(b, x);
        if (r.status == solve::SolveStatus::Ok) {
            m_residual.noalias() = b - A * x;
            const double nb = b.norm();
            r.relative_residual = nb > 0 ? m_residual.norm() / nb : m_residual.norm();
        }
        return r;
    }
    const solve::PcgResult p = m_pcg.solve(A, b, x);
    r.status = p.status;
    r.iterations = p.iterations;
    r.relative_residual = p.relative_residual;
    r.refactored = p.refactored;
    return r;
}

} // namespace polycut::integrate::detail
