// Off-thread CHOLMOD analysis and factorization, so that a cut (new sparsity pattern, new size)
// does not stall the tick (DESIGN.md sec. 4): PCG keeps stepping with its previous
// preconditioner while a worker thread factors the new matrix.
#pragma once

#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/sparse.hpp"

#include <memory>
#include <optional>

namespace polycut::solve {

/// One worker thread that factors the latest matrix handed to start(). A newer start()
/// supersedes an older one: a job already running is finished (CHOLMOD cannot be interrupted)
/// and its result dropped. All members are thread-safe; the destructor cancels and joins.
class BackgroundCholesky {
public:
    BackgroundCholesky();
    ~BackgroundCholesky();
    BackgroundCholesky(const BackgroundCholesky&) = delete;
    BackgroundCholesky& operator=(const BackgroundCholesky&) = delete;

    /// Queues analyze + factorize of A (symmetric, full storage); A is moved in, so pass a copy
    /// (std::move it if the caller no longer needs it). Supersedes any earlier job.
    void start(SparseMatrix A);
    /// Like start(), but reuses `solver` (its symbolic analysis when A has the same pattern).
    void start(SparseMatrix A, CholmodSolver&& solver);
    /// Drops the queued job and any result not yet taken; a running job finishes unseen.
    void cancel();
    /// True when the latest job has finished (successfully or not) and is not taken yet.
    bool ready() const;
    /// True while a job is queued or running.
    bool busy() const;
    /// Blocks until the latest job has finished (returns at once if there is none).
    void wait() const;
    /// Outcome of the latest finished job (NotReady if none finished since the last start()).
    SolveStatus status() const;
    /// The factor of the latest job if it finished with status Ok, else nullopt. Consumes the
    /// result: ready() is false afterwards.
    std::optional<CholmodSolver> take();
    /// Number of the rows of the matrix of the latest job (0 if none).
    long size() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve
