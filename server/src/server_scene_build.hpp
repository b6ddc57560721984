// A `load_scene` built on a worker thread while the loop goes on ticking and streaming the old
// scene (issue 14 item 3; docs/decisions/0060). The loop starts one SceneBuild, polls done()
// between ticks and installs the result itself: the session is only ever touched by the loop
// thread, the worker touches only the scene it builds.
#pragma once

#include "server_session.hpp"

#include <atomic>
#include <memory>
#include <thread>

namespace polycut::server {

class SceneBuild {
public:
    /// Starts building `scene` (Session::build_scene) on a worker thread that runs at a lower
    /// CPU priority (nice +10) than the loop, so the build takes what the ticks leave.
    explicit SceneBuild(PreparedScene scene);
    /// Waits for the worker (a build cannot be interrupted; polycut-server exits without
    /// waiting, see abandoned()).
    ~SceneBuild();
    SceneBuild(const SceneBuild&) = delete;
    SceneBuild& operator=(const SceneBuild&) = delete;

    /// True once the worker has finished (built or failed). Thread-safe.
    bool done() const { return m_state->done.load(std::memory_order_acquire); }
    /// The built simulation or the error (requires done(); once).
    BuiltScene take();
    /// Wall time of the build [ms] (requires done()).
    double build_ms() const { return m_state->build_ms; }

private:
    struct State {
        PreparedScene scene;
        std::optional<BuiltScene> result;
        double build_ms = 0.0;
        std::atomic<bool> done { false };
    };
    std::shared_ptr<State> m_state;
    std::thread m_thread;
};

/// Frees replaced scenes and hands the freed pages back to the system (`malloc_trim`) on a
/// worker thread. On the loop thread, dropping a 41k-tet scene and trimming took ~140 ms
/// (docs/reliability.md).
class SceneDisposal {
public:
    SceneDisposal() = default;
    /// Waits for the last disposal.
    ~SceneDisposal();
    SceneDisposal(const SceneDisposal&) = delete;
    SceneDisposal& operator=(const SceneDisposal&) = delete;

    /// Destroys `old` (may be null: only the trim) and then trims the heap, on a worker thread.
    /// Waits for the previous disposal first (normally long finished).
    void dispose(std::unique_ptr<sim::Simulation> old);

private:
    std::thread m_thread;
};

} // namespace polycut::server
