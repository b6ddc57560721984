// Sweep-triangle sanity checks (pure geometry on arrays): a cut's triangles must be finite and
// not degenerate (zero area relative to their size).
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

/// Checks every triangle; the first defect yields -32002 CutRejected pointing at
/// `pointer`/k (k = the triangle's index).
std::optional<RpcError> check_sweep_triangles(std::span<const Triangle3> triangles,
    std::string_view pointer, double min_quality = kMinTriangleQuality);

} // namespace polycut::protocol
