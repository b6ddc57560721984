#include "polycut/integrate/linear_solver.hpp"

namespace polycut::integrate {
namespace {
solve::PcgOptions pcg_options(const SolverOptions& o) {
    solve::PcgOptions p;
    p.relative_tolerance = o.relative_tolerance;
    p.max_iterations = o.max_iterations;
    p.iteration_budget = o.iteration_budget;
    p.refactor_every = o.refactor_every;
    p.refactor_iterations = o.refactor_iterations;
    p.background_refactor = o.background_refactor;
    p.amg = o.amg;
    p.threads = o.threads;
    p.start_vectors = o.start_vectors;
    switch (o.kind) {
    case LinearSolverKind::PcgBlockJacobi:
        p.preconditioner = solve::Preconditioner::BlockJacobi3;
        break;
    case LinearSolverKind::PcgCellBlockJacobi:
        p.preconditioner = solve::Preconditioner::BlockJacobi;
        break;
    case LinearSolverKind::PcgLagged:
        p.preconditioner = solve::Preconditioner::LaggedCholesky;
        break;
    case LinearSolverKind::PcgIncompleteCholesky:
        p.preconditioner = solve::Preconditioner::IncompleteCholesky;
        break;
    case LinearSolverKind::PcgAmg:
        p.preconditioner = solve::Preconditioner::Amg;
        break;
    case LinearSolverKind::PcgTwoLevel:
        p.preconditioner = solve::Preconditioner::TwoLevel;
        // The smoother's blocks from the set-up's matrix: on the DG organ the same iterations
        // as blocks of every solve's matrix, whose inversion cost more than the rest of the
        // preconditioner (docs/decisions/0024).
        p.two_level_fresh_smoother = false;
        break;
    default:
        p.preconditioner = solve::Preconditioner::Jacobi;
    }
    return p;
}
} // namespace

LinearSolver::LinearSolver(const SolverOptions& options)
    : m_options(options)
    , m_pcg(pcg_options(options)) { }

bool LinearSolver::remap(const solve::RowRemap& m) {
    return m_options.kind == LinearSolverKind::PcgAmg && m_pcg.remap_preconditioner(m);
}

bool LinearSolver::prepare(const solve::SparseMatrix& A) {
    return wants_prepare() && m_pcg.prepare(A) == solve::SolveStatus::Ok;
}

void LinearSolver::reset() {
    m_cholmod = solve::CholmodSolver();
    m_pcg.reset();
}

LinearSolveResult LinearSolver::solve(
    const solve::SparseMatrix& A, const solve::Vector& b, solve::Vector& x) {
    LinearSolveResult r;
    if (A.rows() == 0) {
        x.resize(0);
        return r;
    }
    if (m_options.kind == LinearSolverKind::Cholmod) {
        r.status = m_cholmod.factorize(A);
        if (r.status == solve::SolveStatus::Ok)
            r.status = m_cholmod.solve(b, x);
        if (r.status == solve::SolveStatus::Ok) {
            const double bn = b.norm();
            r.relative_residual = bn > 0 ? (b - A * x).norm() / bn : 0.0;
        }
        return r;
    }
    if (m_options.kind == LinearSolverKind::CgRelaxation) {
        // 002 sec. 3.1: CG on K u = f with only products K d; the fixed DOFs are already
        // eliminated from the reduced system, so no residual entry needs zeroing here.
        if (x.size() != b.size() || !x.allFinite())
            x = solve::Vector::Zero(b.size());
        m_no_fixed.assign(std::size_t(b.size()), false);
        const auto apply
            = [&A](const solve::Vector& d, solve::Vector& Ad) { Ad.noalias() = A * d; };
        const solve::RelaxationResult rr = m_relaxation.relax(
            apply, b, m_no_fixed, x, m_options.relative_tolerance, m_options.max_iterations);
        r.iterations = rr.iterations;
        r.relative_residual = rr.relative_residual;
        r.status = !x.allFinite() ? solve::SolveStatus::NonFinite
            : rr.breakdown        ? solve::SolveStatus::NotPositiveDefinite
            : rr.converged        ? solve::SolveStatus::Ok
                                  : solve::SolveStatus::NotConverged;
        return r;
    }
    solve::PcgResult p = m_pcg.solve(A, b, x);
    if (p.status == solve::SolveStatus::NotReady && m_options.kind == LinearSolverKind::PcgAmg) {
        // hypre/MPI unusable in this process (m_pcg.setup_error() says why): go on with Jacobi
        // rather than fail every step
        r.warning = "AMG preconditioner unavailable (" + m_pcg.setup_error()
            + "): using Jacobi PCG from now on";
        solve::PcgOptions jacobi = m_pcg.options();
        jacobi.preconditioner = solve::Preconditioner::Jacobi;
        m_pcg = solve::PcgSolver(jacobi);
        p = m_pcg.solve(A, b, x);
    }
    r.status = p.status;
    r.iterations = p.iterations;
    r.relative_residual = p.relative_residual;
    r.budget_reached = p.budget_reached;
    return r;
}

} // namespace polycut::integrate
