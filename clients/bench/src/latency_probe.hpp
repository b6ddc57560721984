// The latency benchmark's measurement loop (polycut-bench): against a running polycut-server it
// measures (a) the control round-trip time of a small request (get_stats), (b) command-to-visible
// latency: from sending a command (apply_force, scalpel or cut) to receiving the first stream
// frame whose header lists its id in `applied`, and (c) the server's own tick times (the step
// report of every stream frame, frame arrival intervals, get_stats overrun counters), under
// load: a command rate and extra stream subscribers.
#pragma once

#include "polycut/common/stats.hpp"

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace polycut::bench {

/// Which command the probe sends.
enum class ProbeCommand { ApplyForce, Scalpel, Cut };

/// Settings of a benchmark run.
struct ProbeOptions {
    std::string server = "tcp://127.0.0.1:5555"; ///< control endpoint
    std::string stream; ///< stream endpoint ("" = from hello)
    double duration_s = 10; ///< measuring time [s]
    double warmup_s = 0.5; ///< time before measuring (connections settle) [s]
    double command_rate_hz = 20; ///< commands per second [Hz], > 0
    double rtt_rate_hz = 20; ///< get_stats requests per second [Hz], > 0
    int subscribers = 0; ///< extra stream subscribers (load on the server's PUB)
    ProbeCommand command = ProbeCommand::ApplyForce;
    /// Load this scene (by name, from the server's scene directory) before measuring ("" = keep).
    std::string scene;
    double force_n = 0.02; ///< apply_force magnitude [N] (downwards, small)
    double reply_timeout_s = 5; ///< [s]
};

/// Everything measured.
struct ProbeResult {
    std::vector<double> control_rtt_ms; ///< get_stats round trips [ms]
    std::vector<double> command_ack_ms; ///< command sent -> its reply [ms]
    std::vector<double> visible_ms; ///< command sent -> first frame listing it as applied [ms]
    std::vector<double> visible_ticks; ///< that frame's tick - the last tick seen when sending
    std::vector<double> step_ms; ///< server step time per tick, from the stream headers [ms]
    std::vector<double> frame_interval_ms; ///< arrival interval of consecutive frames [ms]
    long commands_sent = 0;
    long commands_visible = 0; ///< of which seen in a frame's `applied`
    long command_errors = 0; ///< error replies
    long frames = 0; ///< stream frames received while measuring
    long gaps = 0; ///< seq gaps
    std::vector<long> extra_frames; ///< frames each extra subscriber received
    double rate_hz = 0; ///< server tick rate [Hz]
    std::int64_t ticks = 0; ///< server ticks during the measurement
    std::uint64_t ticks_over_budget = 0; ///< increase during the measurement
    double worst_tick_ms = 0; ///< server's worst tick so far (get_stats) [ms]
    double stats_step_ms_p50 = 0; ///< last get_stats step_ms_p50 [ms]
    double stats_step_ms_p99 = 0; ///< last get_stats step_ms_p99 [ms]
    std::uint64_t stream_dropped = 0; ///< increase of the server's stream_dropped
    std::uint32_t vertex_count = 0; ///< surface size
    std::uint32_t triangle_count = 0;
    std::string scene; ///< scene name (from hello)
    double wall_s = 0; ///< [s]
};

/// Runs the benchmark. Throws polycut::Error if the server does not answer or is paused (no
/// stream frames), InputError for bad options. `stop` ends the measurement early.
ProbeResult run_probe(const ProbeOptions& options, const std::atomic<bool>& stop);

} // namespace polycut::bench
