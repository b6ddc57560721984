// Armed cut failures for the tests of the undo path (see fault_injection.hpp).
#include "polycut/cut/fault_injection.hpp"

#include "polycut/common/error.hpp"

#include <atomic>

namespace polycut::cut {

namespace {
std::atomic<int> g_armed { 0 };
} // namespace

void inject_cut_failures(int count) {
    g_armed.store(count > 0 ? count : 0);
}

int injected_cut_failures() {
    return g_armed.load();
}

void detail::fail_if_injected() {
    int armed = g_armed.load();
    while (armed > 0) {
        if (g_armed.compare_exchange_weak(armed, armed - 1))
            throw Error("cut", "injected failure (test hook)");
    }
}

} // namespace polycut::cut
