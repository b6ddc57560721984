// SceneBuild: Session::build_scene on a worker thread (see server_scene_build.hpp).
#include "server_scene_build.hpp"

#include <chrono>
#include <cstdio>
#include <malloc.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace polycut::server {

namespace {

/// Niceness of the build thread: CFS gives a nice-0 loop thread ~10x its share of a core.
constexpr int kBuildNice = 10;

} // namespace

SceneBuild::SceneBuild(PreparedScene scene)
    : m_state(std::make_shared<State>()) {
    m_state->scene = std::move(scene);
    m_thread = std::thread([state = m_state] {
        // Linux: a thread's nice value is per thread (the tid as PRIO_PROCESS id). Failing to
        // lower it costs only fairness.
        (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), kBuildNice);
        const auto t0 = std::chrono::steady_clock::now();
        state->result.emplace(Session::build_scene(std::move(state->scene)));
        state->build_ms
            = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count();
        state->done.store(true, std::memory_order_release);
    });
}

SceneBuild::~SceneBuild() {
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

BuiltScene SceneBuild::take() {
    if (m_thread.joinable()) {
        m_thread.join();
    }
    return std::move(*m_state->result);
}

SceneDisposal::~SceneDisposal() {
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

void SceneDisposal::dispose(std::unique_ptr<sim::Simulation> old) {
    if (m_thread.joinable()) {
        m_thread.join();
    }
    m_thread = std::thread([old = std::move(old)]() mutable {
        const bool had_scene = old != nullptr;
        const auto t0 = std::chrono::steady_clock::now();
        old.reset();
        const auto t1 = std::chrono::steady_clock::now();
        ::malloc_trim(0);
        const auto t2 = std::chrono::steady_clock::now();
        if (had_scene) {
            std::fprintf(stderr,
                "[info] polycut-server: replaced scene freed in %.1f ms, heap trimmed in %.1f ms "
                "(off the loop)\n",
                std::chrono::duration<double, std::milli>(t1 - t0).count(),
                std::chrono::duration<double, std::milli>(t2 - t1).count());
        }
    });
}

} // namespace polycut::server
