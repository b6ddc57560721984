// Offline recording: replays a session's command log (`polycut-server --record-commands`) on a
// fresh simulation, tick by tick, and renders every tick (or every k-th), with no dropped
// frames and the same bytes every run. This is the only part of polycut-record that links the
// simulation (through the server library's Session and replay, so the replay is exactly the
// server's); it lives in its own library, polycut_record_offline, built only when the
// simulation is configured.
#pragma once

#include "frame_recorder.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace polycut::record {

/// Settings of an offline recording.
struct OfflineOptions {
    std::string scene_file; ///< scene to start from (overrides the log header's scene_file)
    std::string commands; ///< command log (JSON lines); "" = no commands, just step the scene
    long every = 1; ///< render every k-th tick (ticks 1, 1 + k, 1 + 2k, ...), k >= 1
    long max_frames = 0; ///< stop after this many frames (0 = to the log's end marker)
    std::string scene_dir; ///< directory for load_scene by name ("" = the log header's)
    bool progress = true; ///< progress bar on stderr
    /// Also write every recorded tick's volume mesh as DIR/frame_TICK.vtu (displacement,
    /// velocity, stress, von Mises, cut tag) and the collection DIR/series.pvd ("" = none).
    std::string vtu_dir;
};

/// What an offline recording did.
struct OfflineSummary {
    std::int64_t ticks = 0; ///< ticks simulated
    long frames = 0; ///< frames recorded (rendered and/or written as .vtu)
    std::size_t commands = 0; ///< commands replayed
    std::size_t rejected = 0; ///< commands the session refused (should be 0)
    std::string state_hash; ///< final session state hash, 16 hex digits
    std::uint64_t topology_version = 0; ///< at the end
    double fps = 0; ///< video frame rate used: 1 / (dt * every) [1/s]
    double wall_s = 0; ///< [s]
    double step_ms_mean = 0; ///< mean simulation step [ms]
    double render_ms_mean = 0; ///< mean render + write per frame [ms]
};

/// Makes the frame sink once the frame rate is known (it comes from the scene's time step); a
/// factory returning null renders nothing (a --vtu only recording).
using SinkFactory = std::function<std::unique_ptr<FrameSink>(double fps)>;

/// True when this build has offline support (the simulation was configured).
bool offline_available();

/// Replays and renders. Throws polycut::Error (FileError for the log, SceneError for the scene)
/// or InputError for bad options.
OfflineSummary record_offline(
    const OfflineOptions& options, const RecordRender& render, const SinkFactory& make_sink);

} // namespace polycut::record
