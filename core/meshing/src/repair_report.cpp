// The repair report as a log line, and the scene spellings of the repair and components modes
// (no CGAL: the runner and the scene parser use these).
#include "polycut/meshing/repair.hpp"

#include <array>
#include <cstdio>
#include <utility>

namespace polycut::meshing {

namespace {

constexpr std::array<std::pair<RepairMode, std::string_view>, 4> kRepairNames { {
    { RepairMode::Auto, "auto" },
    { RepairMode::None, "none" },
    { RepairMode::Pmp, "pmp" },
    { RepairMode::Wrap, "wrap" },
} };

constexpr std::array<std::pair<ComponentsMode, std::string_view>, 3> kComponentsNames { {
    { ComponentsMode::Union, "union" },
    { ComponentsMode::Largest, "largest" },
    { ComponentsMode::Refuse, "refuse" },
} };

/// ", <n> <what>" when n > 0.
std::string count(Index n, const char* what) {
    return n > 0 ? ", " + std::to_string(n) + " " + what : std::string();
}

} // namespace

std::string_view to_string(RepairMode mode) {
    for (const auto& [m, name] : kRepairNames)
        if (m == mode)
            return name;
    return "?";
}

std::string_view to_string(ComponentsMode mode) {
    for (const auto& [m, name] : kComponentsNames)
        if (m == mode)
            return name;
    return "?";
}

std::optional<RepairMode> parse_repair_mode(std::string_view text) {
    for (const auto& [m, name] : kRepairNames)
        if (name == text)
            return m;
    return std::nullopt;
}

std::optional<ComponentsMode> parse_components_mode(std::string_view text) {
    for (const auto& [m, name] : kComponentsNames)
        if (name == text)
            return m;
    return std::nullopt;
}

std::string RepairReport::summary() const {
    std::string s = applied + " (repair \"" + std::string(to_string(mode))
        + "\"): " + std::to_string(faces_in) + " -> " + std::to_string(faces_out) + " faces";
    s += count(duplicate_vertices_merged, "duplicate vertices merged");
    s += count(duplicate_faces_removed, "duplicate faces");
    s += count(invalid_faces_removed, "invalid faces");
    s += count(degenerate_faces_removed, "degenerate faces");
    s += count(non_manifold_vertices_split, "non-manifold vertices split");
    s += count(border_edges_in, "border edges");
    s += count(holes_filled, "holes filled");
    s += count(holes_unfilled, "holes left open");
    s += count(self_intersections_in, "self-intersecting face pairs");
    if (self_intersections_in > 0)
        s += " (" + std::to_string(self_intersections_out) + " after PMP)";
    if (components_in > 1 || components_out > 1)
        s += ", components " + std::to_string(components_in) + " -> "
            + std::to_string(components_out);
    char buf[200];
    if (wrapped) {
        std::snprintf(
            buf, sizeof buf, ", wrapped (alpha %.3g m, offset %.3g m)", wrap_alpha, wrap_offset);
        s += buf;
    }
    std::snprintf(buf, sizeof buf, ", volume %.4e -> %.4e m^3 (%+.2f %%), %.0f ms", volume_in,
        volume_out, 100 * volume_change, time_ms);
    return s + buf;
}

} // namespace polycut::meshing
