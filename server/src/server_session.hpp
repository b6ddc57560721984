// The simulation side of the server: one sim::Simulation plus the state the protocol adds on top
// of it (wire ids of forces and grabs, open scalpel strokes, the scene directory). Every command
// that changes the simulation goes through Session::apply, both live and when a command log is
// replayed, so the two give identical states (DESIGN.md sec. 5, determinism). No sockets here.
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"
#include "polycut/protocol/params.hpp"
#include "polycut/protocol/results.hpp"
#include "polycut/sim/simulation.hpp"
#include "server_strokes.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace polycut::server {

/// Session settings.
struct SessionConfig {
    /// Directory `load_scene {"name"}` resolves against: <scene_dir>/<name>.json.
    std::string scene_dir = "assets/scenes";
    /// Scalpel stroke bookkeeping limits (per client).
    StrokeLimits strokes;
    /// Largest scene a load may build, as sim::estimate() puts it [bytes]; 0 = no budget.
    std::uint64_t max_scene_bytes = 0;
    /// Sweep triangles the cuts of one tick may apply (protocol::Limits); 0 = no limit.
    std::uint32_t cut_triangles_per_tick = protocol::Limits {}.cut_triangles_per_tick;
};

/// What applying a command did besides its result.
struct Applied {
    protocol::Result result;
    bool scene_changed = false; ///< load_scene or reset: a new surface topology from tick 0
    std::string scene_reason; ///< "load" or "reset" when scene_changed
};

/// Outcome of Session::apply.
using ApplyOutcome = protocol::Expected<Applied, protocol::RpcError>;

/// A `load_scene`'s scene: read, parsed and within the memory budget, not built yet.
struct PreparedScene {
    scene::Scene scene;
    std::string name; ///< the scene's name on the wire ("inline" for an inline scene)
    bool named = false; ///< from the scene directory (errors point at /params/name)
};

/// A scene built by Session::build_scene, or why not.
using BuiltScene = protocol::Expected<std::unique_ptr<sim::Simulation>, protocol::RpcError>;

/// Scalpel sweep triangles of one stroke that could not be cut (the cut was undone, nothing
/// changed): the server publishes each as a `rejected` event.
struct SweepRejection {
    std::string client; ///< routing identity of the stroke's client
    /// "scalpel" (a stroke's sweep), "cut" (the deferred part of a `cut`) or "end_stroke" (the
    /// deferred finish of a stroke)
    std::string method = "scalpel";
    std::uint64_t stroke = 0; ///< the client's stroke id (0 for "cut")
    std::uint32_t triangles = 0; ///< sweep triangles dropped
    protocol::RpcError error; ///< -32002 with the reason
};

/// The simulation with the protocol's bookkeeping. Not thread-safe: the server loop owns it.
class Session {
public:
    explicit Session(SessionConfig config = {});
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    /// Loads a scene file given on the command line (not through the wire: any path is allowed).
    /// Throws polycut::Error subclasses (SceneError, FileError, MeshError) on failure.
    void load_scene_file(const std::string& path);

    /// The cheap half of `load_scene` (on the loop thread): resolves the name, parses the scene,
    /// checks inline paths and the memory budget. Builds nothing; never throws.
    protocol::Expected<PreparedScene, protocol::RpcError> prepare_scene(
        const protocol::LoadSceneParams& p) const;
    /// The expensive half: meshes and builds the simulation. Touches no session state, so it
    /// may run on another thread while the session goes on. Never throws: a failure is -32001
    /// pointing into the request.
    static BuiltScene build_scene(PreparedScene scene);
    /// Replaces the simulation by a built one and returns what `load_scene` answers; forces,
    /// grabs, tools and strokes of the old scene are dropped. The old simulation goes to
    /// `replaced` when given (the caller frees it where it likes), else it is destroyed here.
    Applied install_scene(std::unique_ptr<sim::Simulation> sim, std::string name,
        std::unique_ptr<sim::Simulation>* replaced = nullptr);

    /// True when the method changes the simulation (and so is recorded in the command log):
    /// load_scene, reset, apply_force, remove_force, grab, move_grab, release, cut, scalpel,
    /// end_stroke, tool_create, tool_move, tool_remove.
    static bool is_mutation(protocol::Method method);

    /// Applies a mutation at the current tick boundary on behalf of `client` (the routing
    /// identity; scalpel strokes are per client). Never throws; on error nothing changed.
    /// `now_s` is a monotonic wall time [s] used only to expire idle strokes.
    /// A `scalpel` sent as a request (`reply_expected`) is cut at once, so its reply can carry
    /// the outcome; as a notification it waits for the next tick.
    ApplyOutcome apply(const protocol::Params& params, std::string_view client, double now_s,
        bool reply_expected = false);

    /// Advances one tick (no-op report when no scene is loaded): first applies the scalpel
    /// sweep triangles queued since the last tick (one cut per stroke), then steps. Never
    /// throws; a stroke whose sweep could not be cut, or whose cut the step undid, is listed in
    /// take_rejections().
    sim::StepReport step();
    /// Applies the queued scalpel sweep triangles now (end_stroke, step), one cut per stroke in
    /// arrival order. Never throws; strokes that could not be cut (nothing changed for them) go
    /// to take_rejections().
    void flush_sweeps();
    /// Finishes the sweep of a stroke (end_stroke) or of a `cut` request (`from_cut`, stroke 0)
    /// whose triangles are all cut: Simulation::end_stroke; a finish that fails (undone) goes to
    /// take_rejections() under the method "end_stroke" or "cut".
    void finish_sweep(const std::string& client, bool from_cut, std::uint64_t stroke);
    /// Strokes whose sweeps were rejected since the last call (clears the list).
    std::vector<SweepRejection> take_rejections() { return std::exchange(m_rejections, {}); }
    /// Wall time of the cuts applied since the last call [ms] (resets it).
    double take_cut_ms() {
        const double ms = m_cut_ms;
        m_cut_ms = 0.0;
        return ms;
    }
    /// Sweep triangles waiting for the next tick: scalpel samples since the last tick, and what
    /// the cut budget (scene cutting.max_cells_per_tick) deferred.
    std::size_t pending_sweep_triangles() const;

    /// Drops everything kept for a client (its open strokes).
    void drop_client(std::string_view client);
    /// Drops strokes idle for longer than the limit.
    void expire(double now_s);

    bool has_scene() const { return m_sim != nullptr; }
    /// The simulation (requires has_scene()).
    const sim::Simulation& simulation() const { return *m_sim; }
    /// Name of the loaded scene ("inline" for an inline scene), empty when none.
    const std::string& scene_name() const { return m_scene_name; }
    /// Ticks completed since the scene was loaded or reset.
    std::int64_t tick() const;
    /// Simulated time [s].
    double sim_time() const;
    /// Topology version of the surface (0 when no scene).
    std::uint64_t topology_version() const;
    std::uint32_t active_forces() const { return static_cast<std::uint32_t>(m_forces.size()); }
    std::uint32_t active_grabs() const { return static_cast<std::uint32_t>(m_grabs.size()); }
    std::uint32_t active_tools() const { return static_cast<std::uint32_t>(m_tools.size()); }
    /// What the tissue does to every tool (by wire id) and obstacle after the last tick.
    std::vector<protocol::ContactReport> contacts() const;
    std::size_t open_strokes() const { return m_strokes.size(); }
    std::uint32_t cell_count() const { return m_cells; }

    /// Hash of the whole session state: the simulation's state_hash, its tick and topology
    /// version, the active forces, grabs and tools with their wire ids, and the open strokes.
    std::uint64_t state_hash() const;

    /// The next tick number a command applied now takes effect in (tick() + 1).
    std::int64_t effect_tick() const { return tick() + 1; }

private:
    ApplyOutcome load_scene(const protocol::LoadSceneParams& p);
    ApplyOutcome reset();
    ApplyOutcome apply_force(const protocol::ApplyForceParams& p);
    ApplyOutcome remove_force(const protocol::RemoveForceParams& p);
    ApplyOutcome grab(const protocol::GrabParams& p);
    ApplyOutcome move_grab(const protocol::MoveGrabParams& p);
    ApplyOutcome release(const protocol::ReleaseParams& p);
    ApplyOutcome cut(const protocol::CutParams& p, std::string_view client);
    ApplyOutcome scalpel(const protocol::ScalpelParams& p, std::string_view client, double now_s,
        bool reply_expected);
    ApplyOutcome end_stroke(const protocol::EndStrokeParams& p, std::string_view client);
    // Tools (server_session_tool.cpp)
    ApplyOutcome tool_create(const protocol::ToolCreateParams& p);
    ApplyOutcome tool_move(const protocol::ToolMoveParams& p);
    ApplyOutcome tool_remove(const protocol::ToolRemoveParams& p);
    /// Runs the simulation's cut; never throws. A rejected triangle becomes -32002 pointing at
    /// it under `pointer` (`pointer`/i/k); a cut that failed (and was undone) -32002 pointing
    /// at `pointer`.
    protocol::Expected<sim::CutSummary, protocol::RpcError> run_cut(
        const std::vector<std::array<Vec3, 3>>& triangles, std::string_view pointer);
    /// Installs `sim`; returns the simulation it replaced (null when none).
    std::unique_ptr<sim::Simulation> install(
        std::unique_ptr<sim::Simulation> sim, std::string name);
    void prune_expired_forces();
    /// Queues the sweep of `stroke` from its last swept sample to (a, b) and makes (a, b) the
    /// last swept sample; returns the triangles queued (0 to 2).
    std::uint32_t queue_sweep(Stroke& stroke, const protocol::Vector3& a,
        const protocol::Vector3& b, std::string_view client, std::uint64_t id);
    /// Removes and returns the pending rejection of `stroke` (the caller answers it itself).
    std::optional<protocol::RpcError> take_rejection(std::string_view client, std::uint64_t stroke);

    struct ForceEntry {
        long sim_id = 0;
        double expires = 0; ///< sim time [s]; 0 = never
        std::array<double, 7> spec {}; ///< point, force, radius (for the state hash)
    };
    struct GrabEntry {
        long sim_id = 0;
        protocol::Vector3 target {};
        std::array<double, 5> spec {}; ///< point, stiffness, radius
    };

    SessionConfig m_config;
    std::unique_ptr<sim::Simulation> m_sim;
    std::string m_scene_name;
    std::uint32_t m_cells = 0;
    std::map<std::uint64_t, ForceEntry> m_forces; ///< wire id -> entry
    std::map<std::uint64_t, GrabEntry> m_grabs;
    struct ToolEntry {
        long sim_id = 0;
        std::array<double, 7> pose {}; ///< position, orientation w x y z (for the state hash)
    };
    std::map<std::uint64_t, ToolEntry> m_tools;
    std::uint64_t m_next_id = 1; ///< wire ids of forces and grabs, never reused
    StrokeTable m_strokes;
    /// Scalpel sweep triangles received since the last tick, applied together at its start:
    /// one cut per tick however fast the blade samples arrive, so a slow cut cannot queue up
    /// one cut per sample behind it.
    struct PendingSweep {
        std::string client; ///< routing identity
        std::uint64_t stroke = 0;
        std::array<Vec3, 3> triangle; ///< world space [m]
        bool from_cut = false; ///< the deferred rest of a `cut` request (stroke 0)
        /// Not a triangle: the stroke's end_stroke came while triangles of it were deferred
        /// (or, with from_cut, a `cut` request's triangles were); the stroke (the request's
        /// sweep) is finished once they are cut.
        bool end = false;
    };
    std::vector<PendingSweep> m_pending_sweep;
    /// Strokes cut since the last step (their cuts go when that step undoes them).
    struct StrokeCut {
        std::string client;
        bool from_cut = false;
        std::uint64_t stroke = 0;
        std::uint32_t triangles = 0;
    };
    std::vector<StrokeCut> m_cut_since_step;
    std::vector<SweepRejection> m_rejections;
    double m_cut_ms = 0.0; ///< cut time since take_cut_ms [ms]
    /// Sweep triangles the cuts may still apply before the next step (cut_triangles_per_tick).
    std::uint32_t m_cut_triangles_left = 0;
};

} // namespace polycut::server
