// Method names (the contract of issue 6 item 2).
#include "polycut/protocol/methods.hpp"

namespace polycut::protocol {

namespace {
constexpr std::array<std::string_view, kMethodCount> kNames
    = { "hello", "load_scene", "reset", "pause", "resume", "step", "set_rate", "apply_force",
          "remove_force", "grab", "move_grab", "release", "cut", "scalpel", "end_stroke",
          "get_surface", "get_stats", "shutdown", "tool_create", "tool_move", "tool_remove" };
} // namespace

std::string_view method_name(Method method) {
    return kNames.at(static_cast<std::size_t>(method));
}

std::optional<Method> method_from_name(std::string_view name) {
    for (std::size_t i = 0; i < kNames.size(); ++i) {
        if (kNames[i] == name) {
            return static_cast<Method>(i);
        }
    }
    return std::nullopt;
}

} // namespace polycut::protocol
