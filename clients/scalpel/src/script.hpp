// Scalpel scripts (assets/scripts/*.json, format in assets/scripts/README.md): a timed list of
// world-space events (scene loads, blade strokes, forces, grabs and moves, cuts, waits),
// expanded into a timeline of protocol requests the player sends at their times.
#pragma once

#include "polycut/protocol/params.hpp"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace polycut::scalpel {

/// A script that cannot be read; `what()` names the JSON pointer of the bad field.
class ScriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// One request of the timeline.
struct Action {
    double t = 0.0; ///< send time after the script start [s]
    protocol::Params params; ///< the request (ids of forces and grabs filled in at send time)
    /// Store the id this request creates (apply_force, grab) under this name; the player waits
    /// for the reply before going on.
    std::string bind_as;
    /// Name of a force or grab whose id goes into params (remove_force, move_grab, release).
    std::string ref;
    bool wait = false; ///< wait for the reply before the next action (load_scene, ...)
};

/// A parsed script.
struct Script {
    std::string name;
    std::string description;
    std::vector<Action> actions; ///< sorted by t (stable)
    double end_t = 0.0; ///< the player runs at least until this time [s]
};

/// Parses a script (JSON text). Throws ScriptError.
Script parse_script(const std::string& json_text);
/// Reads and parses a script file. Throws ScriptError.
Script load_script(const std::string& path);

} // namespace polycut::scalpel
