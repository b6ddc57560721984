// Preconditioned conjugate gradients (Hestenes-Stiefel with a symmetric preconditioner M):
//   r = b - A x, z = M^-1 r, p = z; repeat: alpha = r.z / p.Ap, x += alpha p, r -= alpha Ap,
//   z = M^-1 r, beta = r.z_new / r.z_old, p = z + beta p; stop at ||r|| <= tol ||b||.
// Work vectors live in Impl and keep their size between solves: no allocation per iteration
// and none per solve once the size is stable (DESIGN.md sec. 4, STYLE.md "hot loop").
#include "polycut/solve/pcg.hpp"

#include "amg_preconditioner.hpp"
#include "background_priority.hpp"
#include "jacobi.hpp"
#include "polycut/common/error.hpp"
#include "polycut/solve/background_cholesky.hpp"
#include "start_space.hpp"
#include "two_level.hpp"

#include <Eigen/Cholesky>
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <string>
#include <vector>

namespace polycut::solve {

struct PcgSolver::Impl {
    PcgOptions options;
    // work vectors, sized n
    Vector r, z, p, q;
    // Jacobi: inverse diagonal (n); BlockJacobi3: inverse 3x3 diagonal blocks (n / 3) plus
    // inverse diagonal for the trailing n % 3 rows
    Vector inv_diag;
    std::vector<Eigen::Matrix3d> inv_blocks;
    // BlockJacobi: block starts (set_blocks) and the inverse blocks, column-major, packed
    std::vector<long> block_starts;
    std::vector<double> inv_cell_blocks;
    // TwoLevel: smoother plus lagged Galerkin coarse space
    detail::TwoLevelPreconditioner two_level;
    // LaggedCholesky
    CholmodSolver factor;
    int solves_since_refactor = 0;
    bool refactor_requested = false;
    /// Iterations of the first solve after the last set-up of a lagged preconditioner (-1:
    /// none yet): what a fresh one achieves on these systems
    int fresh_iterations = -1;
    bool installed = false; ///< a factor was installed since the last solve
    int refactorizations = 0;
    std::unique_ptr<BackgroundCholesky> background;
    // IncompleteCholesky: Eigen's IC with limited fill (Lin & More 1999) on the AMD ordering,
    // lagged like the CHOLMOD factor.
    Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> ic;
    long ic_size = -1;
    // Amg: BoomerAMG hierarchy of an earlier matrix, lagged like the CHOLMOD factor
    detail::AmgPreconditioner amg;
    std::string setup_error;
    // Amg with background_solves > 0: the hierarchy being set up on a worker thread, the solves
    // left until it is installed (-1: none under way), and the coordinates of the rigid modes.
    std::future<std::unique_ptr<detail::AmgPreconditioner>> amg_job;
    int amg_handover = -1;
    Vector amg_coordinates;
    // cuts since the job started: replayed on its hierarchy at the hand-over
    std::vector<RowRemap> job_remaps;
    int remaps_since_setup = 0; ///< cuts the installed hierarchy was carried over
    /// Solves since the hierarchy was last carried over a cut (remap_preconditioner): a
    /// requested background set-up starts only once this reaches AmgOptions::refresh_delay.
    int since_remap = std::numeric_limits<int>::max();
    int threads = 1; ///< of the matrix passes now: options.threads, or 1 (follow_background)
    /// The last solutions, a Galerkin start for the next solve (PcgOptions::start_vectors)
    detail::StartSpace start;
    double start_norm = 0; ///< ||b - A x0|| of the last iterate() call's start
    bool budget_reached = false; ///< the last iterate() call stopped at the iteration budget

    /// One thread while a background set-up runs (AmgOptions::background_serial), the configured
    /// count otherwise. Called where the job starts or is handed over: at fixed solves.
    void follow_background() {
        const int want = options.amg.background_serial && amg_handover >= 0 ? 1 : options.threads;
        if (want == threads)
            return;
        threads = want;
        amg.set_threads(want);
    }

    explicit Impl(PcgOptions o)
        : options(o)
        , amg(o.amg)
        , start(o.start_vectors) {
        options.threads = std::max(options.threads, 1);
        threads = options.threads;
        amg.set_threads(threads);
        if (options.background_refactor)
            background = std::make_unique<BackgroundCholesky>();
    }

    void resize(long n) {
        if (r.size() == n)
            return;
        r.resize(n);
        z.resize(n);
        p.resize(n);
        q.resize(n);
    }

    SolveStatus setup_jacobi(const SparseMatrix& A) { return detail::invert_diagonal(A, inv_diag); }

    SolveStatus setup_block_jacobi(const SparseMatrix& A) {
        return detail::invert_node_blocks(A, inv_blocks, inv_diag);
    }

    SolveStatus setup_cell_blocks(const SparseMatrix& A) {
        return detail::invert_diagonal_blocks(A, block_starts, inv_cell_blocks);
    }

    /// z = M^-1 r (A: the system matrix, for the fused AMG cycle).
    SolveStatus apply(Preconditioner use, const SparseMatrix& A) {
        switch (use) {
        case Preconditioner::None:
            z = r;
            return SolveStatus::Ok;
        case Preconditioner::Jacobi:
            z = inv_diag.cwiseProduct(r);
            return SolveStatus::Ok;
        case Preconditioner::BlockJacobi3: {
            const long blocks = static_cast<long>(inv_blocks.size());
            for (long b = 0; b < blocks; ++b)
                z.segment<3>(3 * b).noalias()
                    = inv_blocks[static_cast<size_t>(b)] * r.segment<3>(3 * b);
            for (long j = 3 * blocks; j < r.size(); ++j)
                z[j] = inv_diag[j] * r[j];
            return SolveStatus::Ok;
        }
        case Preconditioner::BlockJacobi: {
            std::size_t at = 0;
            for (std::size_t b = 0; b + 1 < block_starts.size(); ++b) {
                const long s = block_starts[b], size = block_starts[b + 1] - s;
                z.segment(s, size).noalias()
                    = Eigen::Map<const Eigen::MatrixXd>(inv_cell_blocks.data() + at, size, size)
                    * r.segment(s, size);
                at += std::size_t(size * size);
            }
            return SolveStatus::Ok;
        }
        case Preconditioner::LaggedCholesky:
            return factor.solve(r, z);
        case Preconditioner::IncompleteCholesky:
            z = ic.solve(r);
            return SolveStatus::Ok;
        case Preconditioner::Amg:
            return amg.apply(A, r, z);
        case Preconditioner::TwoLevel:
            return two_level.apply(r, z);
        }
        return SolveStatus::NotReady;
    }

    /// PCG iterations from x; adds to `iterations`.
    SolveStatus iterate(const SparseMatrix& A, const Vector& b, Vector& x, double target,
        Preconditioner use, int& iterations) {
        multiply_symmetric(A, x, q, threads);
        r = b - q;
        double r_norm = r.norm();
        if (!std::isfinite(r_norm))
            return SolveStatus::NonFinite;
        // An initial guess worse than none is dropped: PCG minimizes the error's A-norm, and
        // |x* - x|_A^2 = |x*|_A^2 + 2 E(x) with E(x) = x.A x / 2 - b.x, so x0 is worse than zero
        // when E(x0) > 0 (A x0 is at hand: two dot products). The integrator's warm start (the
        // last step's dv, or its extrapolation) is such a guess when the motion reverses from
        // step to step, as the lips of a fresh cut ring after a stroke on the 5k organ. There,
        // PCG needed 10-34 iterations at tolerance 0.3 for ~7 ticks, against 1-3 while cutting,
        // where every cut restarts from zero. (Comparing |b - A x0| with |b| instead dropped
        // good guesses too: 5 -> 8 iterations on the sagging organ.)
        if (x.size() > 0 && 0.5 * x.dot(q) - b.dot(x) > 0) {
            x.setZero();
            r = b;
            r_norm = b.norm();
        }
        start_norm = r_norm;
        if (r_norm <= target)
            return SolveStatus::Ok;
        if (const SolveStatus s = apply(use, A); s != SolveStatus::Ok)
            return s;
        p = z;
        double rz = r.dot(z);
        for (;;) {
            if (iterations >= options.max_iterations)
                return SolveStatus::NotConverged;
            multiply_symmetric(A, p, q, threads);
            const double pq = p.dot(q);
            if (!std::isfinite(pq))
                return SolveStatus::NonFinite;
            if (!(pq > 0))
                return SolveStatus::NotPositiveDefinite;
            const double alpha = rz / pq;
            x += alpha * p;
            r -= alpha * q;
            ++iterations;
            r_norm = r.norm();
            if (!std::isfinite(r_norm))
                return SolveStatus::NonFinite;
            if (r_norm <= target)
                return SolveStatus::Ok;
            if (options.iteration_budget > 0 && iterations >= options.iteration_budget) {
                budget_reached = true;
                return SolveStatus::Ok;
            }
            if (const SolveStatus s = apply(use, A); s != SolveStatus::Ok)
                return s;
            const double rz_new = r.dot(z);
            if (!(rz_new > 0))
                return std::isfinite(rz_new) ? SolveStatus::NotPositiveDefinite
                                             : SolveStatus::NonFinite;
            const double beta = rz_new / rz;
            rz = rz_new;
            p = z + beta * p;
        }
    }

    bool refactor_due(const SparseMatrix& A) const {
        return !factor.ready() || factor.size() != A.rows() || !factor.same_pattern(A)
            || (options.refactor_every > 0 && solves_since_refactor >= options.refactor_every)
            || refactor_requested;
    }

    /// The lagged factor is new: restart the refactor schedule.
    void mark_refactored() {
        remaps_since_setup = 0;
        solves_since_refactor = 0;
        refactor_requested = false;
        installed = true;
    }

    void install(CholmodSolver&& f) {
        factor = std::move(f);
        mark_refactored();
    }

    /// Waits for a background set-up under way and drops it (hypre is used by one thread at a
    /// time, and a foreground set-up supersedes it).
    void drop_amg_job() {
        if (amg_job.valid())
            amg_job.get();
        amg_handover = -1;
        job_remaps.clear();
    }

    /// Starts a set-up of A on a worker thread (A and the coordinates are copied).
    void start_amg_job(const SparseMatrix& A) {
        drop_amg_job();
        ++refactorizations;
        amg_job = std::async(std::launch::async,
            [A = SparseMatrix(A), coordinates = amg_coordinates, o = options.amg] {
                detail::run_in_background();
                auto fresh = std::make_unique<detail::AmgPreconditioner>(o);
                if (coordinates.size() == A.rows())
                    fresh->set_coordinates(coordinates);
                if (fresh->setup(A) != SolveStatus::Ok)
                    fresh.reset();
                return fresh;
            });
        amg_handover = options.amg.background_solves;
        solves_since_refactor = 0;
        refactor_requested = false;
    }

    /// The hand-over of a background set-up: installs it when it fits A (a cut since it started
    /// changed the size: dropped, the carried-over hierarchy goes on).
    void finish_amg_job(const SparseMatrix& A) {
        std::unique_ptr<detail::AmgPreconditioner> fresh = amg_job.get();
        amg_handover = -1;
        std::vector<RowRemap> remaps = std::move(job_remaps);
        job_remaps.clear();
        // the cuts since the job started renumbered the unknowns: carry the fresh hierarchy
        // over them as the installed one was
        for (const RowRemap& m : remaps)
            if (fresh && !fresh->remap(m))
                fresh.reset();
        if (!fresh || fresh->size() != A.rows())
            return;
        fresh->set_threads(threads);
        amg.swap(*fresh);
        mark_refactored();
        remaps_since_setup = int(remaps.size());
        installed = true;
    }

    /// (Re)builds the AMG hierarchy from A.
    SolveStatus setup_amg(const SparseMatrix& A) {
        drop_amg_job();
        ++refactorizations;
        amg.set_coordinates(amg_coordinates); // kept here, handed over only when needed
        const SolveStatus s = amg.setup(A);
        setup_error = s == SolveStatus::NotReady ? amg.error() : std::string();
        if (s != SolveStatus::Ok) {
            amg.clear();
            return s;
        }
        mark_refactored();
        return SolveStatus::Ok;
    }

    /// (Re)builds the two-level preconditioner's coarse part and smoother from A.
    SolveStatus setup_two_level(const SparseMatrix& A) {
        ++refactorizations;
        two_level.set_smoother(block_starts, options.two_level_weight);
        if (const SolveStatus s = two_level.setup(A); s != SolveStatus::Ok)
            return s;
        mark_refactored();
        return SolveStatus::Ok;
    }

    /// Chooses and prepares the preconditioner of this solve.
    SolveStatus prepare(const SparseMatrix& A, PcgResult& result) {
        Preconditioner use = options.preconditioner;
        if (use == Preconditioner::LaggedCholesky) {
            if (background) {
                if (background->ready())
                    if (std::optional<CholmodSolver> f = background->take())
                        install(std::move(*f));
                if (refactor_due(A) && !background->busy()) {
                    background->start(A); // copies A: the caller may change it next step
                    ++refactorizations;
                    solves_since_refactor = 0;
                    refactor_requested = false;
                }
                if (!factor.ready() || factor.size() != A.rows())
                    use = Preconditioner::BlockJacobi3;
            } else if (refactor_due(A)) {
                ++refactorizations;
                if (const SolveStatus s = factor.factorize(A); s != SolveStatus::Ok)
                    return s;
                mark_refactored();
            }
        }
        if (use == Preconditioner::IncompleteCholesky) {
            const bool due = ic_size != A.rows()
                || (options.refactor_every > 0 && solves_since_refactor >= options.refactor_every)
                || refactor_requested;
            if (due) {
                ++refactorizations;
                if (ic_size != A.rows())
                    ic.analyzePattern(A);
                ic.factorize(A);
                ic_size = A.rows();
                if (ic.info() != Eigen::Success) {
                    ic_size = -1;
                    return SolveStatus::NotPositiveDefinite;
                }
                mark_refactored();
            }
        }
        if (use == Preconditioner::Amg) {
            if (amg_handover == 0)
                finish_amg_job(A);
            const bool missing = amg.size() != A.rows();
            const bool scheduled
                = options.refactor_every > 0 && solves_since_refactor >= options.refactor_every;
            const bool due = missing || scheduled || refactor_requested;
            if (due && !missing && options.amg.background_solves > 0) {
                if (amg_handover < 0 && (since_remap >= options.amg.refresh_delay || scheduled))
                    start_amg_job(A);
            } else if (due) {
                if (const SolveStatus s = setup_amg(A); s != SolveStatus::Ok)
                    return s;
            }
            if (amg_handover > 0)
                --amg_handover;
            if (since_remap < std::numeric_limits<int>::max())
                ++since_remap;
            follow_background();
        }
        if (use == Preconditioner::TwoLevel) {
            if (two_level.space_rows() != A.rows() || block_starts.size() < 2
                || block_starts.back() != A.rows()) {
                use = Preconditioner::BlockJacobi; // no coarse space of this size
            } else {
                const bool due = two_level.size() != A.rows()
                    || (options.refactor_every > 0
                        && solves_since_refactor >= options.refactor_every)
                    || refactor_requested;
                two_level.set_smoother(block_starts, options.two_level_weight);
                if (due || two_level.size() != A.rows()) {
                    if (const SolveStatus s = setup_two_level(A); s != SolveStatus::Ok)
                        return s;
                } else if (options.two_level_fresh_smoother) {
                    if (const SolveStatus s = two_level.refresh_smoother(A); s != SolveStatus::Ok)
                        return s;
                }
            }
        }
        if (use == Preconditioner::BlockJacobi
            && (block_starts.size() < 2 || block_starts.back() != A.rows()))
            use = Preconditioner::BlockJacobi3; // no blocks of this size: 3x3 ones
        result.used = use;
        switch (use) {
        case Preconditioner::Jacobi:
            return setup_jacobi(A);
        case Preconditioner::BlockJacobi:
            return setup_cell_blocks(A);
        case Preconditioner::BlockJacobi3:
            return setup_block_jacobi(A);
        default:
            return SolveStatus::Ok;
        }
    }
};

PcgSolver::PcgSolver(PcgOptions options)
    : m_impl(std::make_unique<Impl>(options)) { }

PcgSolver::~PcgSolver() = default;
PcgSolver::PcgSolver(PcgSolver&&) noexcept = default;
PcgSolver& PcgSolver::operator=(PcgSolver&&) noexcept = default;

const PcgOptions& PcgSolver::options() const {
    return m_impl->options;
}

void PcgSolver::reset() {
    m_impl->factor = CholmodSolver {};
    m_impl->amg.clear();
    m_impl->ic_size = -1;
    m_impl->two_level.clear();
    m_impl->drop_amg_job();
    m_impl->solves_since_refactor = 0;
    m_impl->refactor_requested = false;
    m_impl->fresh_iterations = -1;
    m_impl->since_remap = std::numeric_limits<int>::max();
    m_impl->installed = false;
    m_impl->start.clear();
    if (m_impl->background)
        m_impl->background->cancel();
}

PcgResult PcgSolver::solve(const SparseMatrix& A, const Vector& b, Vector& x) {
    Impl& impl = *m_impl;
    PcgResult result;
    const long n = A.rows();
    if (A.cols() != n || b.size() != n)
        throw InputError("PcgSolver::solve",
            "matrix " + std::to_string(A.rows()) + " x " + std::to_string(A.cols())
                + " does not match right-hand side of " + std::to_string(b.size()) + " rows");
    if (x.size() != n || !x.allFinite())
        x.setZero(n);
    if (!b.allFinite()) {
        result.status = SolveStatus::NonFinite;
        return result;
    }
    const double b_norm = b.norm();
    if (b_norm == 0) {
        x.setZero();
        return result;
    }
    impl.resize(n);
    impl.amg.matrix_changed(); // A's values are new (or may be)
    result.status = impl.prepare(A, result);
    result.refactored = impl.installed;
    impl.installed = false;
    if (result.status != SolveStatus::Ok)
        return result;

    const double target
        = std::max(impl.options.relative_tolerance * b_norm, impl.options.absolute_tolerance);
    impl.budget_reached = false;
    impl.start.project(A, b, x, impl.threads);
    result.status = impl.iterate(A, b, x, target, result.used, result.iterations);
    result.start_residual = impl.start_norm / b_norm;
    int iterations_with_factor = result.iterations;
    // A stale lagged factor (or AMG hierarchy) that cannot reach the tolerance: refactor once and
    // go on from x.
    const bool lagged = (result.used == Preconditioner::LaggedCholesky && !impl.background)
        || result.used == Preconditioner::Amg || result.used == Preconditioner::TwoLevel;
    if (result.status == SolveStatus::NotConverged && lagged && !result.refactored) {
        if (result.used == Preconditioner::Amg) {
            result.status = impl.setup_amg(A);
        } else if (result.used == Preconditioner::TwoLevel) {
            result.status = impl.setup_two_level(A);
        } else {
            ++impl.refactorizations;
            result.status = impl.factor.factorize(A);
        }
        impl.mark_refactored();
        impl.installed = false;
        result.refactored = true;
        if (result.status == SolveStatus::Ok) {
            int more = 0; // a fresh iteration budget
            result.status = impl.iterate(A, b, x, target, result.used, more);
            result.iterations += more;
            iterations_with_factor = more;
        }
    }

    result.budget_reached = impl.budget_reached;
    if (result.status == SolveStatus::Ok)
        impl.start.push(x, b, impl.r);
    ++impl.solves_since_refactor;
    // Set up again only when a solve needs more than refactor_iterations and clearly more than
    // a fresh set-up did: where even a fresh hierarchy needs more than the threshold (organ
    // meshes, issue 18), a set-up after every solve bought nothing but the set-up.
    if (result.refactored && lagged)
        impl.fresh_iterations = iterations_with_factor;
    const double grown = impl.options.refactor_growth * double(impl.fresh_iterations);
    if (iterations_with_factor > impl.options.refactor_iterations
        && double(iterations_with_factor) > grown)
        impl.refactor_requested = true;
    // iterate() leaves r = b - A x (recomputed at its start, then updated with x): the recursive
    // residual, equal to the true one up to round-off, without another SpMV
    result.relative_residual = impl.r.norm() / b_norm;
    return result;
}

SolveStatus PcgSolver::prepare(const SparseMatrix& A) {
    Impl& impl = *m_impl;
    if (impl.options.preconditioner != Preconditioner::Amg || A.rows() == 0 || A.cols() != A.rows()
        || impl.amg.size() == A.rows())
        return SolveStatus::Ok;
    impl.resize(A.rows());
    impl.amg.matrix_changed();
    PcgResult unused;
    return impl.prepare(A, unused); // a missing hierarchy is set up in the foreground
}

void PcgSolver::set_absolute_tolerance(double tolerance) {
    m_impl->options.absolute_tolerance = std::isfinite(tolerance) ? std::max(tolerance, 0.0) : 0.0;
}

void PcgSolver::set_preconditioner_factor(CholmodSolver&& factor) {
    m_impl->install(std::move(factor));
}

void PcgSolver::finish_background_refactor() {
    if (!m_impl->background)
        return;
    m_impl->background->wait();
    if (m_impl->background->ready())
        if (std::optional<CholmodSolver> f = m_impl->background->take())
            m_impl->install(std::move(*f));
}

void PcgSolver::set_coordinates(const Vector& coordinates) {
    if (m_impl->options.preconditioner == Preconditioner::Amg
        && m_impl->options.amg.rigid_body_modes) {
        m_impl->amg_coordinates = coordinates;
    }
}

void PcgSolver::set_blocks(std::vector<long> starts) {
    m_impl->block_starts = std::move(starts);
}

void PcgSolver::set_coarse_space(const SparseMatrix& P) {
    m_impl->two_level.set_coarse_space(P);
}

bool PcgSolver::remap_preconditioner(const RowRemap& m) {
    Impl& impl = *m_impl;
    impl.start.remap(m); // the kept solutions follow the unknowns
    if (impl.options.preconditioner != Preconditioner::Amg || !impl.amg.remap(m))
        return false;
    ++impl.remaps_since_setup;
    impl.since_remap = 0;
    if (impl.amg_handover >= 0)
        impl.job_remaps.push_back(m);
    return true;
}

void PcgSolver::forget_solutions() {
    m_impl->start.clear();
}

void PcgSolver::request_refresh() {
    Impl& impl = *m_impl;
    if (impl.options.preconditioner == Preconditioner::Amg && impl.remaps_since_setup > 0
        && impl.amg_handover < 0)
        impl.refactor_requested = true;
}

int PcgSolver::threads() const {
    return m_impl->threads;
}

int PcgSolver::refactorizations() const {
    return m_impl->refactorizations;
}

int PcgSolver::amg_levels() const {
    return m_impl->amg.levels();
}

int PcgSolver::amg_threaded_levels() const {
    return m_impl->amg.threaded_levels();
}

const std::string& PcgSolver::setup_error() const {
    return m_impl->setup_error;
}

} // namespace polycut::solve
