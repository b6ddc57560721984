// Worker thread for BackgroundCholesky. Jobs carry a generation number; only the result of the
// latest generation is kept, so a cut arriving while an earlier refactorization runs simply
// supersedes it.
#include "polycut/solve/background_cholesky.hpp"

#include "background_priority.hpp"

#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

namespace polycut::solve {

struct BackgroundCholesky::Impl {
    mutable std::mutex mutex;
    mutable std::condition_variable changed;
    // job slot (guarded by mutex)
    std::optional<SparseMatrix> pending;
    std::optional<CholmodSolver> pending_solver;
    long generation = 0; ///< generation of the latest start()
    long running_generation = -1; ///< generation being factored by the worker (-1: idle)
    // result slot (guarded by mutex)
    std::optional<CholmodSolver> result;
    SolveStatus result_status = SolveStatus::NotReady;
    bool finished = false; ///< the latest generation has finished and is not taken
    long rows = 0;
    bool stop = false;
    std::thread worker; // last member: started after the state above exists

    Impl()
        : worker([this] { run(); }) { }

    ~Impl() {
        {
            std::lock_guard lock(mutex);
            stop = true;
            pending.reset();
        }
        changed.notify_all();
        worker.join();
    }

    void run() {
        detail::run_in_background();
        std::unique_lock lock(mutex);
        for (;;) {
            changed.wait(lock, [this] { return stop || pending.has_value(); });
            if (stop)
                return;
            SparseMatrix A = std::move(*pending);
            pending.reset();
            CholmodSolver solver = pending_solver ? std::move(*pending_solver) : CholmodSolver();
            pending_solver.reset();
            const long job = generation;
            running_generation = job;
            lock.unlock();

            SolveStatus status = SolveStatus::NotReady;
            try {
                status = solver.factorize(A);
            } catch (...) {
                status = SolveStatus::NotReady; // out of memory or invalid input: no factor
            }

            lock.lock();
            running_generation = -1;
            if (job == generation && !stop) {
                result_status = status;
                result.reset();
                if (status == SolveStatus::Ok)
                    result.emplace(std::move(solver));
                finished = true;
            }
            changed.notify_all();
        }
    }
};

BackgroundCholesky::BackgroundCholesky()
    : m_impl(std::make_unique<Impl>()) { }

BackgroundCholesky::~BackgroundCholesky() = default;

void BackgroundCholesky::start(SparseMatrix A) {
    {
        std::lock_guard lock(m_impl->mutex);
        m_impl->rows = A.rows();
        m_impl->pending = std::move(A);
        m_impl->pending_solver.reset();
        ++m_impl->generation;
        m_impl->result.reset();
        m_impl->result_status = SolveStatus::NotReady;
        m_impl->finished = false;
    }
    m_impl->changed.notify_all();
}

void BackgroundCholesky::start(SparseMatrix A, CholmodSolver&& solver) {
    {
        std::lock_guard lock(m_impl->mutex);
        m_impl->rows = A.rows();
        m_impl->pending = std::move(A);
        m_impl->pending_solver.emplace(std::move(solver));
        ++m_impl->generation;
        m_impl->result.reset();
        m_impl->result_status = SolveStatus::NotReady;
        m_impl->finished = false;
    }
    m_impl->changed.notify_all();
}

void BackgroundCholesky::cancel() {
    {
        std::lock_guard lock(m_impl->mutex);
        m_impl->pending.reset();
        m_impl->pending_solver.reset();
        ++m_impl->generation;
        m_impl->result.reset();
        m_impl->result_status = SolveStatus::NotReady;
        m_impl->finished = false;
        m_impl->rows = 0;
    }
    m_impl->changed.notify_all();
}

bool BackgroundCholesky::ready() const {
    std::lock_guard lock(m_impl->mutex);
    return m_impl->finished;
}

bool BackgroundCholesky::busy() const {
    std::lock_guard lock(m_impl->mutex);
    return m_impl->pending.has_value() || m_impl->running_generation == m_impl->generation;
}

void BackgroundCholesky::wait() const {
    std::unique_lock lock(m_impl->mutex);
    m_impl->changed.wait(lock, [this] {
        return !m_impl->pending.has_value() && m_impl->running_generation != m_impl->generation;
    });
}

SolveStatus BackgroundCholesky::status() const {
    std::lock_guard lock(m_impl->mutex);
    return m_impl->result_status;
}

std::optional<CholmodSolver> BackgroundCholesky::take() {
    std::lock_guard lock(m_impl->mutex);
    if (!m_impl->finished)
        return std::nullopt;
    m_impl->finished = false;
    std::optional<CholmodSolver> out = std::move(m_impl->result);
    m_impl->result.reset();
    return out;
}

long BackgroundCholesky::size() const {
    std::lock_guard lock(m_impl->mutex);
    return m_impl->rows;
}

} // namespace polycut::solve
