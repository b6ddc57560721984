// The command log (`polycut-server --record-commands FILE`) and its replay. One JSON object per
// line:
//   {"polycut_command_log": 1, "scene_file": "/abs/default.json" | null, "scene_dir": "..."}
//   {"tick": 12, "client": "00a1b2c3d4", "request": {"jsonrpc": "2.0", "method": "cut", ...}}
//   {"tick": 240, "end": true}
// `tick` is the number of ticks completed when the command was applied (it takes effect in tick
// tick + 1); `client` is the hex routing identity (scalpel strokes are per client); the request
// has its binary arrays inlined as JSON numbers (float32 values are exact in JSON). Only
// commands that changed the simulation are logged, in the order they were applied. Replaying the
// log on a fresh Session gives the same states tick by tick (determinism, DESIGN.md sec. 5).
#pragma once

#include "polycut/protocol/request.hpp"
#include "server_session.hpp"

#include <cstdint>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace polycut::server {

/// Hex text of a routing identity (what the log stores as "client").
std::string client_hex(std::string_view identity);

/// Writes a command log. Each line is flushed when written.
class CommandLog {
public:
    /// Creates (truncates) `path` and writes the header line. Throws polycut::FileError.
    CommandLog(const std::string& path, const std::optional<std::string>& scene_file,
        const std::string& scene_dir);
    /// Appends an applied command.
    void record(std::int64_t tick, std::string_view client, const protocol::Request& request);
    /// Appends the end marker: the session ran until `tick`.
    void end(std::int64_t tick);

private:
    std::ofstream m_out;
};

/// What a replay did.
struct ReplaySummary {
    std::int64_t tick = 0; ///< ticks completed at the end
    std::size_t commands = 0; ///< commands applied
    std::size_t rejected = 0; ///< commands the session answered with an error (should be 0)
    /// scalpel strokes whose sweep was rejected at a tick (as live: same cuts fail the same way)
    std::size_t sweeps_rejected = 0;
    std::uint64_t state_hash = 0; ///< Session::state_hash at the end
    std::uint64_t topology_version = 0;
    std::string scene; ///< scene name at the end
};

/// Called after every tick the replay steps (e.g. the offline renderer records a frame).
using ReplayTickCallback = std::function<void(const Session&, const sim::StepReport&)>;

/// Replays a log into `session` (which should be fresh): loads the header's scene file, then
/// steps the session up to each command's tick and applies it, and steps to the end marker (or
/// to `until_tick` when given, whichever comes first). The session's own
/// scene directory resolves scene names (the header's `scene_dir` is informative).
/// Throws polycut::FileError for an unreadable or malformed log.
ReplaySummary replay_command_log(const std::string& path, Session& session,
    const ReplayTickCallback& on_tick = {}, std::optional<std::int64_t> until_tick = {});

} // namespace polycut::server
