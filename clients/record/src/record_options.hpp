// The command line of polycut-record, parsed into settings (separate from main for tests).
#pragma once

#include "frame_recorder.hpp"
#include "live_recorder.hpp"
#include "offline_recorder.hpp"

#include <optional>
#include <string>
#include <vector>

namespace polycut::record {

/// Everything polycut-record was asked to do.
struct RecordCommand {
    bool help = false;
    bool offline = false; ///< --offline SCENE given
    LiveOptions live;
    OfflineOptions offline_options;
    RecordRender render;
    std::string png_dir; ///< --png-dir (exactly one of png_dir, mp4)
    std::string mp4; ///< --mp4
    std::optional<double> fps; ///< --fps: video frame rate override [1/s]
    bool quiet = false; ///< no progress bar or info lines
    /// Scheduling niceness for the recorder and its ffmpeg (0..19): live recordings yield the
    /// CPU to the server's tick on a small machine (docs/perf.md "Recording overhead").
    int nice = 10;
};

/// Usage text.
std::string record_usage();

/// Parses argv[1..]. Throws InputError naming the option for anything wrong (unknown option,
/// missing or bad value, both or neither of --png-dir / --mp4, --frames with --seconds).
RecordCommand parse_record_command(const std::vector<std::string>& args);

} // namespace polycut::record
