// Plays a scalpel script against a polycut-server: sends each action at its time over a DEALER
// (requests pipelined; creations and scene loads wait for their reply), reads the surface
// stream meanwhile, and summarizes what happened (acknowledgement latencies, errors, topology
// versions and ticks seen) as one JSON document.
#pragma once

#include "script.hpp"

#include <string>

namespace polycut::scalpel {

/// Player settings.
struct PlayOptions {
    std::string server = "tcp://127.0.0.1:5555"; ///< control endpoint
    double reply_timeout_s = 10.0; ///< give up waiting for a reply after this long [s]
    bool shutdown_after = false; ///< send `shutdown` when the script is done
    bool subscribe = true; ///< read the surface stream (frames, seq gaps, topology versions)
};

/// Plays `script` and returns the summary as compact JSON text. Throws std::runtime_error when
/// the server cannot be reached.
std::string play(const Script& script, const PlayOptions& options, int& errors_out);

/// Sends only `shutdown` (no script). Returns true when the server acknowledged it.
bool send_shutdown(const PlayOptions& options);

} // namespace polycut::scalpel
