// Sweep-triangle shape (pure geometry on arrays): the server skips the triangles of a scalpel
// sample that did not move the blade. The triangles of a `cut` are validated once, by core/cut's
// pipeline (docs/decisions/0010), not here.
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/limits.hpp"
#include "polycut/protocol/params.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace polycut::protocol {

/// Shape quality q = 4 sqrt(3) area / (l0^2 + l1^2 + l2^2): 1 for an equilateral triangle, 0 for
/// collinear or coincident corners; scale-invariant. Returns 0 for non-finite input.
double triangle_quality(const Triangle3& triangle);

/// Why a triangle is unusable as a sweep triangle, or nullopt if it is fine: non-finite
/// coordinates, coincident corners, or quality < min_quality.
std::optional<std::string> triangle_defect(
    const Triangle3& triangle, double min_quality = kMinTriangleQuality);

} // namespace polycut::protocol
