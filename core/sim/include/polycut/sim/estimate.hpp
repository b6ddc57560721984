// What a scene will cost before anything is built (issue 14 item 3): the server refuses a scene
// whose estimate exceeds its memory budget instead of finding out through std::bad_alloc.
#pragma once

#include "polycut/scene/scene.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace polycut::sim {

/// Size and memory of the model a scene asks for, from the scene alone (no meshing, no file
/// read beyond its size). Upper-bound-minded: 1.2-1.7x the heap a built box scene holds after a
/// step (test_estimate).
struct SceneEstimate {
    double cells = 0; ///< cells of the mesh (tets, hexes or polyhedra)
    double nodes_per_cell = 4; ///< typical nodes of one cell
    double bytes = 0; ///< peak memory of the built simulation [bytes]
    bool known = true; ///< false: the geometry's size cannot be told before meshing it
    std::string basis; ///< how `cells` was found, for the error message
};

/// Estimates the scene. Calibrated on this machine (docs/reliability.md): a tet costs ~3.7 kB
/// and a hex ~21 kB built (element matrices, pattern, solver work arrays), ~4.5 x 8 bytes per
/// entry of its (3n)^2 element matrix plus 1 kB.
SceneEstimate estimate(const scene::Scene& scene);

/// Why the scene does not fit a memory budget [bytes] (0 = none), as a message naming the
/// estimate and the budget; nullopt when it fits or cannot be estimated.
std::optional<std::string> over_budget(const scene::Scene& scene, std::uint64_t budget);

} // namespace polycut::sim
