// Private: process-wide MPI + hypre runtime for the BoomerAMG preconditioner. MPI is started once,
// lazily, as a singleton process (no mpirun), on MPI_COMM_SELF only; it is finalized at exit once
// no AMG object is alive. Never include from a public header.
#pragma once

#include <mutex>
#include <string>

namespace polycut::solve::detail {

/// Takes a reference on the runtime, initializing MPI and hypre on first use. Returns false (and
/// the reason in `why`) if they could not be started; no reference is taken then.
bool hypre_acquire(std::string& why);
/// Drops a reference taken by a successful hypre_acquire().
void hypre_release();
/// hypre keeps global state (error flag, handles) and Open MPI is initialized with at most
/// MPI_THREAD_SERIALIZED: every hypre call runs under this lock.
std::mutex& hypre_mutex();

} // namespace polycut::solve::detail
