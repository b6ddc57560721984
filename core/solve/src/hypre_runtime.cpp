// MPI and hypre lifetime for the AMG preconditioner. polycut runs as one process without a
// launcher, so MPI starts as an Open MPI "singleton". Before MPI_Init we default (without
// overriding what the user set) the Open MPI parameters that make a singleton quiet and
// self-contained:
// - ess_singleton_isolated = 1: no orted helper daemon is forked (0.15 s instead of 0.5 s
//   start-up).
// - btl = self, pml = ob1: only the process itself is a peer; no network or shared-memory
//   transports are probed (no UCX/OFI warnings, no fork() warning). osc = ^ucx: the same for
//   one-sided communication.
// - orte_tmpdir_base = a fresh directory of our own: every isolated singleton names its session
//   directory <base>/ompi.<host>.<uid>/jf.0/1/0, the same path in every process. With the
//   shared /tmp base, one process finalizing removes jf.0 while another creates it, and the
//   other's MPI_Init aborts ("A call to mkdir was unable to create the desired directory ...
//   jf.0", Open MPI issue #3818; seen in CI under ctest -j2). The directory
//   ($TMPDIR or /tmp)/polycut-mpi-XXXXXX is made with mkdtemp, named to Open MPI for its
//   MPI_Init only (child processes make their own), and removed after MPI_Finalize.
// Running as root needs no OMPI_ALLOW_RUN_AS_ROOT: that check is in mpirun, not in MPI_Init.
// If a launcher started us (OMPI_COMM_WORLD_SIZE / PMI_RANK / PMIX_RANK set), nothing is touched.
// MPI_Finalize runs at exit once the last AMG object is gone (a later one, e.g. a static
// solver destroyed after the exit handler, finalizes when it is released).
#include "hypre_runtime.hpp"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

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
    std::string session_base; ///< our own Open MPI session directory base ("" if none)
};

Runtime& runtime() {
    static Runtime* r = new Runtime; // never destroyed: used from the exit handler
    return *r;
}

#ifdef POLYCUT_HAVE_HYPRE
void set_default(const char* name, const char* value) {
    setenv(name, value, 0); // 0: keep the user's value
}

/// Makes a private Open MPI session directory base unless the user chose one; see the header
/// comment. Returns the directory made ("" when none was made).
std::string make_session_base() {
    if (std::getenv("OMPI_MCA_orte_tmpdir_base"))
        return {};
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/polycut-mpi-XXXXXX";
    if (!mkdtemp(pattern.data()))
        return {}; // Open MPI then uses its own default
    setenv("OMPI_MCA_orte_tmpdir_base", pattern.c_str(), 1);
    return pattern;
}

void remove_session_base(Runtime& r) {
    if (r.session_base.empty())
        return;
    std::error_code ec; // best effort: a left-over empty directory in /tmp harms nothing
    std::filesystem::remove_all(r.session_base, ec);
    r.session_base.clear();
}

void finalize_locked(Runtime& r) {
    if (r.finalized || !r.ok)
        return;
    r.finalized = true;
    HYPRE_Finalize();
    int mpi_finalized = 0;
    MPI_Finalized(&mpi_finalized);
    if (r.mpi_ours && !mpi_finalized) {
        MPI_Finalize();
        remove_session_base(r);
    }
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
            r.session_base = make_session_base();
        }
        int provided = 0;
        const int init = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
        // Open MPI has read its parameters: processes we start (a server, a test's child)
        // make their own session directory instead of sharing ours.
        if (!r.session_base.empty())
            unsetenv("OMPI_MCA_orte_tmpdir_base");
        if (init != MPI_SUCCESS) {
            r.error = "MPI_Init_thread failed";
            remove_session_base(r);
            return;
        }
        r.mpi_ours = true;
    }
    // errors on our communicator come back as codes instead of aborting the process
    MPI_Comm_set_errhandler(MPI_COMM_SELF, MPI_ERRORS_RETURN);
    if (HYPRE_Init() != 0) {
        r.error = "HYPRE_Init failed";
        if (r.mpi_ours) {
            MPI_Finalize();
            remove_session_base(r);
        }
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
