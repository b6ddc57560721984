// Live recording: subscribe to a running polycut-server's surface stream and render every
// received frame (or every k-th). Late join and gaps follow the zguide Clone pattern
// (docs/protocol.md "Late joiners and gaps"): SUBscribe first and buffer, then take a
// `get_surface` snapshot over the control channel, drop buffered frames with seq <= the
// snapshot's seq, apply the rest; on a gap (or positions that do not fit the known topology),
// resynchronize with another snapshot unless the next frame carries its own topology.
//
// A receiver thread drains the stream without ever blocking, so the server's PUB never drops
// frames because of the recorder; the calling thread renders from a queue and may lag behind.
#pragma once

#include "frame_recorder.hpp"

#include <atomic>
#include <cstdint>
#include <string>

namespace polycut::record {

/// Settings of a live recording.
struct LiveOptions {
    std::string server = "tcp://127.0.0.1:5555"; ///< control endpoint
    std::string stream; ///< stream endpoint; empty: the one `hello` reports
    long every = 1; ///< render every k-th received frame, k >= 1
    long max_frames = 0; ///< stop after rendering this many frames (0 = no limit)
    double seconds = 0; ///< stop receiving after this wall time [s] (0 = no limit)
    std::size_t max_queue = 2000; ///< frames waiting to be rendered before new ones are dropped
    double reply_timeout_s = 10; ///< hello / get_surface timeout [s]
};

/// What a live recording saw.
struct LiveSummary {
    long received = 0; ///< surface frames accepted (stream frames and snapshots)
    long rendered = 0; ///< frames rendered and written
    long gaps = 0; ///< seq gaps seen on the stream
    long snapshots = 0; ///< get_surface snapshots taken (1 + resyncs)
    long dropped = 0; ///< frames selected for rendering but dropped because the queue was full
    std::uint64_t first_seq = 0; ///< seq of the first rendered frame
    std::uint64_t last_seq = 0; ///< seq of the last rendered frame
    std::int64_t first_tick = 0; ///< tick of the first rendered frame
    std::int64_t last_tick = 0; ///< tick of the last rendered frame
    double server_rate_hz = 0; ///< tick rate `hello` reported [Hz]
    double wall_s = 0; ///< wall time of the whole recording [s]
    double render_ms_mean = 0; ///< mean render + write time per frame [ms]
};

/// Tick rate and stream endpoint from `hello` (throws polycut::Error if the server does not
/// answer within options.reply_timeout_s).
struct ServerInfo {
    std::string stream; ///< stream endpoint
    double rate_hz = 60; ///< [Hz]
};
ServerInfo query_server(const LiveOptions& options);

/// Records until max_frames, seconds, or `stop` becomes true (e.g. set by SIGINT), then drains
/// the queue and finishes the sink. Throws polycut::Error on protocol or output failures.
LiveSummary record_live(const LiveOptions& options, const ServerInfo& server,
    FrameRecorder& recorder, const std::atomic<bool>& stop);

} // namespace polycut::record
