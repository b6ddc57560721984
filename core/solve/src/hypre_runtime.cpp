// MPI and hypre lifetime for the AMG preconditioner. polycut runs as one process without a
// launcher, so MPI starts as an Open MPI "singleton". Before MPI_Init we default (without
// overriding what the user set) the Open MPI parameters that make a singleton quiet and
// self-contained:
//   ess_singleton_isolated = 1   no orted helper daemon is forked (0.15 s instead of 0.5 s
//   start-up) btl = self, pml = ob1        only the process itself is a peer: no network or
//   shared-memory
//                                transports are probed (no UCX/OFI warnings, no fork() warning)
//   osc = ^ucx                   same for one-sided communication
// Running as root needs no OMPI_ALLOW_RUN_AS_ROOT: that check is in mpirun, not in MPI_Init.
// If a launcher started us (OMPI_COMM_WORLD_SIZE / PMI_RANK / PMIX_RANK set), nothing is touched.
// MPI_Finalize runs at exit once the last AMG object is gone (a later one, e.g. a static
// solver destroyed after the exit handler, finalizes when it is released).
#include "hypre_runtime.hpp"

#include <cstdlib>

#ifdef POLYCUT_HAVE_HYPRE
#include <HYPRE_utilities.h>
#include <mpi.h>
#endif

namespace polycut::solve::detail {

namespace {

struct Runtime {
    bool attempted = false;
    bool ok = false;
    std::string error;
    bool mpi_ours = false; ///< MPI was initialized here (so we finalize it)
    bool exiting = false;
    bool finalized = false;
    int live = 0;
};

Runtime& runtime() {
    static Runtime* r = new Runtime; // never destroyed: used from the exit handler
    return *r;
}

#ifdef POLYCUT_HAVE_HYPRE
void set_default(const char* name, const char* value) {
    setenv(name, value, 0); // 0: keep the user's value
}

void finalize_locked(Runtime& r) {
    if (r.finalized || !r.ok)
        return;
    r.finalized = true;
    HYPRE_Finalize();
    int mpi_finalized = 0;
    MPI_Finalized(&mpi_finalized);
    if (r.mpi_ours && !mpi_finalized)
        MPI_Finalize();
}

void at_exit() {
    std::lock_guard lock(hypre_mutex());
    Runtime& r = runtime();
    r.exiting = true;
    if (r.live == 0)
        finalize_locked(r);
}

void initialize_locked(Runtime& r) {
    r.attempted = true;
    int initialized = 0;
    MPI_Initialized(&initialized);
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized) {
        r.error = "MPI was already finalized in this process";
        return;
    }
    if (!initialized) {
        const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_RANK")
            || std::getenv("PMIX_RANK");
        if (!launched) {
            set_default("OMPI_MCA_ess_singleton_isolated", "1");
            set_default("OMPI_MCA_btl", "self");
            set_default("OMPI_MCA_pml", "ob1");
            set_default("OMPI_MCA_osc", "^ucx");
            set_default("OMPI_MCA_btl_base_warn_component_unused", "0");
        }
        int provided = 0;
        if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
            r.error = "MPI_Init_thread failed";
            return;
        }
        r.mpi_ours = true;
    }
    // errors on our communicator come back as codes instead of aborting the process
    MPI_Comm_set_errhandler(MPI_COMM_SELF, MPI_ERRORS_RETURN);
    if (HYPRE_Init() != 0) {
        r.error = "HYPRE_Init failed";
        if (r.mpi_ours)
            MPI_Finalize();
        r.mpi_ours = false;
        return;
    }
    r.ok = true;
    std::atexit(at_exit);
}
#endif

} // namespace

std::mutex& hypre_mutex() {
    static std::mutex* m = new std::mutex; // never destroyed: used from the exit handler
    return *m;
}

bool hypre_acquire(std::string& why) {
#ifdef POLYCUT_HAVE_HYPRE
    std::lock_guard lock(hypre_mutex());
    Runtime& r = runtime();
    if (!r.attempted)
        initialize_locked(r);
    if (r.finalized && r.ok)
        r.error = "hypre was finalized (process exiting)";
    if (!r.ok || r.finalized) {
        why = r.error;
        return false;
    }
    ++r.live;
    return true;
#else
    why = "polycut was built without hypre (libhypre-dev)";
    return false;
#endif
}

void hypre_release() {
#ifdef POLYCUT_HAVE_HYPRE
    std::lock_guard lock(hypre_mutex());
    Runtime& r = runtime();
    if (r.live > 0)
        --r.live;
    if (r.live == 0 && r.exiting)
        finalize_locked(r);
#endif
}

} // namespace polycut::solve::detail
