// OpenBLAS thread control without a link-time dependency on libopenblas: the symbols are looked
// up in the process (libcholmod -> libblas.so.3 -> libopenblas.so.0 on Debian), so the code also
// runs with the reference BLAS, where it does nothing.
#include "polycut/solve/blas_threads.hpp"

#include <cstdlib>
#include <dlfcn.h>
#include <mutex>

namespace polycut::solve {
namespace {

using SetThreads = void (*)(int);
using GetThreads = int (*)();

template <typename F> F lookup(const char* name) {
    return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name));
}

} // namespace

bool set_blas_threads(int threads) {
    static const auto set = lookup<SetThreads>("openblas_set_num_threads");
    if (!set)
        return false;
    set(threads < 1 ? 1 : threads);
    return true;
}

int blas_threads() {
    static const auto get = lookup<GetThreads>("openblas_get_num_threads");
    return get ? get() : 0;
}

void init_blas_threads_once() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (!std::getenv("OPENBLAS_NUM_THREADS"))
            set_blas_threads(1);
    });
}

} // namespace polycut::solve
