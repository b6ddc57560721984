// Typed results of every control method. Every result says at which tick the command took
// effect: `tick` is the first tick whose surface frame reflects it (that frame lists the
// request id in `applied`), or, for queries, the tick the answer reflects.
#pragma once

#include "polycut/protocol/limits.hpp"
#include "polycut/protocol/methods.hpp"
#include "polycut/protocol/stream.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace polycut::protocol {

/// `hello` result.
struct HelloResult {
    std::string protocol = std::string(kProtocolName); ///< "polycut/1"
    std::string server; ///< server name and version, e.g. "polycut-server 0.1.0"
    Limits limits;
    std::vector<std::string> capabilities; ///< method names plus features ("binary_frames")
    std::string stream; ///< PUB endpoint to SUBscribe to, e.g. "tcp://127.0.0.1:5556"
    std::int64_t tick = 0; ///< current tick
    double rate_hz = 60.0; ///< current tick rate [Hz]
    bool running = false; ///< ticking (not paused)
    std::optional<std::string> scene; ///< loaded scene name, absent when none
    bool operator==(const HelloResult&) const = default;
};

/// `load_scene` result.
struct SceneResult {
    std::int64_t tick = 0; ///< 0: a freshly loaded scene starts at tick 0
    std::string name; ///< scene name ("inline" for an inline scene)
    std::uint64_t topology_version = 0;
    std::uint32_t vertex_count = 0; ///< surface vertices
    std::uint32_t triangle_count = 0; ///< surface triangles
    std::uint32_t cell_count = 0; ///< volume cells
    /// The tick the replaced scene had reached when this one was installed (it went on ticking
    /// while this one was built); absent when no scene was loaded before.
    std::optional<std::int64_t> replaced_tick {};
    double build_ms = 0.0; ///< wall time of the build, on the server's build thread [ms]
    /// The parts the scene built, in build order, each with its wall time and the resident memory
    /// it added (sim's build report, docs/scenes.md "What a scene builds"); parts the scene did
    /// not need are absent.
    struct BuildPart {
        std::string name;
        double ms = 0.0; ///< wall time of building it [ms]
        /// resident memory added while it was built [KiB] (0 when the allocator reused freed
        /// memory: an estimate from below)
        std::int64_t rss_kb = 0;
        bool operator==(const BuildPart&) const = default;
    };
    std::vector<BuildPart> build_parts {};
    bool operator==(const SceneResult&) const = default;
};

/// `reset`, `pause`, `resume`, `step`, `set_rate` result: the run state after the command.
struct RunState {
    std::int64_t tick = 0;
    bool running = false;
    double rate_hz = 60.0; ///< [Hz]
    bool operator==(const RunState&) const = default;
};

/// `remove_force`, `move_grab`, `release`, `shutdown`, `tool_move`, `tool_remove` result.
struct Ack {
    std::int64_t tick = 0;
    bool operator==(const Ack&) const = default;
};

/// `apply_force`, `grab`, `tool_create` result: the new object's id (server-assigned, in [1,
/// 2^53)).
struct Created {
    std::uint64_t id = 0;
    std::int64_t tick = 0;
    bool operator==(const Created&) const = default;
};

/// `cut`, `end_stroke` result.
struct CutResult {
    std::int64_t tick = 0;
    std::uint64_t topology_version = 0; ///< after the cut
    std::uint32_t triangles = 0; ///< sweep triangles applied
    /// sweep triangles past the tick's cut budget, cut over the next ticks (stream header
    /// `cut_deferred`; a `rejected` event if they cannot be)
    std::uint32_t deferred = 0;
    bool operator==(const CutResult&) const = default;
};

/// `scalpel` result (when sent as a request rather than a notification).
struct ScalpelResult {
    std::int64_t tick = 0;
    std::uint32_t triangles = 0; ///< sweep triangles this sample added to its stroke (0 or 2)
    bool operator==(const ScalpelResult&) const = default;
};

/// `get_stats` result.
struct Stats {
    std::int64_t tick = 0;
    double sim_time = 0.0; ///< [s]
    bool running = false;
    double rate_hz = 60.0; ///< [Hz]
    std::uint64_t seq = 0; ///< last published stream seq
    std::uint64_t topology_version = 0;
    std::uint32_t vertex_count = 0;
    std::uint32_t triangle_count = 0;
    std::uint32_t cell_count = 0;
    std::uint64_t ticks_over_budget = 0; ///< ticks whose work exceeded 1 / rate_hz
    double worst_tick_ms = 0.0; ///< [ms]
    double step_ms_p50 = 0.0; ///< median step time over the last second [ms]
    double step_ms_p99 = 0.0; ///< [ms]
    std::uint64_t requests = 0; ///< requests received
    std::uint64_t errors = 0; ///< error replies (and rejected notifications)
    std::uint32_t clients = 0; ///< distinct control peers seen in the last 10 s
    std::uint32_t forces = 0; ///< active forces
    std::uint32_t grabs = 0; ///< active grabs
    // Server-side extras (optional on the wire; absent from older servers).
    std::string state_hash; ///< hash of the simulation state, 16 hex digits ("" = not reported)
    std::uint64_t stream_dropped = 0; ///< stream messages the PUB socket refused to queue
    std::uint32_t open_strokes = 0; ///< scalpel strokes open over all clients
    std::uint32_t cached_replies = 0; ///< replies held by the retry cache
    std::uint32_t client_states = 0; ///< control peers the server holds state for
    /// Replies not sent because the client's queue held limits.max_in_flight replies.
    std::uint64_t replies_dropped = 0;
    /// Rejected notifications folded into another `rejected` event of the same client and tick.
    std::uint64_t events_coalesced = 0;
    /// `rejected` events not published because a tick already had its quota of them.
    std::uint64_t events_suppressed = 0;
    /// Messages answered -32004 (rate or JSON byte budget), notifications included.
    std::uint64_t busy = 0;
    std::uint32_t tools = 0; ///< active tools (tool_create)
    /// What the tissue does to every tool and obstacle after the last tick (as the stream's
    /// `contacts`)
    std::vector<ContactReport> contacts;
    double contact_ms = 0.0; ///< contact work of the last tick [ms]
    /// Cuts since the scene was loaded (issue 12 item 4), in rest space: the area of the cut
    /// surface, both lips [m^2]; the area the applied sweep triangles swept inside the uncut
    /// tissue [m^2]; the area swept by cuts that were undone (failed, or taken back with a
    /// failed step) [m^2]; cut_area / (2 (swept_area + swept_area_undone)) (0 before any cut).
    double cut_area = 0.0;
    double swept_area = 0.0;
    double swept_area_undone = 0.0;
    double cut_completeness = 0.0;
    bool operator==(const Stats&) const = default;
};

/// The result of any method. Which alternative a method returns: hello HelloResult; load_scene
/// SceneResult; reset/pause/resume/step/set_rate RunState; remove_force/move_grab/release/
/// shutdown Ack; apply_force/grab Created; cut/end_stroke CutResult; scalpel ScalpelResult;
/// get_surface SurfaceSnapshot; get_stats Stats.
using Result = std::variant<HelloResult, SceneResult, RunState, Ack, Created, CutResult,
    ScalpelResult, SurfaceSnapshot, Stats>;

/// The Result alternative index `method` returns (see Result).
std::size_t result_index(Method method);

} // namespace polycut::protocol
