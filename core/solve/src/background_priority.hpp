// Background set-ups (AMG hierarchies, lagged CHOLMOD factors) run on worker threads beside the
// step's threads. On a machine with as many cores as step threads, a worker at the same priority
// preempts a step thread, and every parallel region of the step then waits for it: on the
// two-core machine the steps around a background set-up took 60-140 ms instead of 15 (live organ
// incision, docs/perf.md). The worker lowers its own scheduling priority so that it runs on the
// time the steps leave idle; the hand-over point (a fixed number of solves) does not change.
#pragma once

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace polycut::solve::detail {

/// Lowest nice value (19) for the calling thread (Linux: per-thread). Best effort.
inline void run_in_background() {
    const auto tid = static_cast<id_t>(::syscall(SYS_gettid));
    (void)::setpriority(PRIO_PROCESS, tid, 19);
}

} // namespace polycut::solve::detail
