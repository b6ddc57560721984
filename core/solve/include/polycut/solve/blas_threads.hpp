// Thread count of the BLAS under CHOLMOD. OpenBLAS defaults to one thread per core, which makes
// timings depend on the machine's load; polycut runs it single-threaded unless told otherwise.
#pragma once

namespace polycut::solve {

/// Sets the number of OpenBLAS threads (process-wide). Returns false if the loaded BLAS is not
/// OpenBLAS (the call is then a no-op).
bool set_blas_threads(int threads);

/// Current number of OpenBLAS threads, or 0 if the loaded BLAS is not OpenBLAS.
int blas_threads();

/// Called by the first CholmodSolver: one thread unless the environment sets
/// OPENBLAS_NUM_THREADS. Idempotent and thread-safe.
void init_blas_threads_once();

} // namespace polycut::solve
