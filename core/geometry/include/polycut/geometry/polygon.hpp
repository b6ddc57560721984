// Planar polygons given as loops of points: normal, area, centroid, planarity.
#pragma once

#include "polycut/common/types.hpp"

#include <span>

namespace polycut::geometry {

/// Newell's vector of a loop: its direction is the normal by the right-hand rule, its length is
/// twice the area [m^2]. Robust for non-convex and slightly non-planar loops.
Vec3 newell_vector(std::span<const Vec3> loop);

/// Unit normal of a loop (right-hand rule); zero vector for a degenerate loop.
Vec3 polygon_normal(std::span<const Vec3> loop);

/// Area of a planar loop [m^2].
double polygon_area(std::span<const Vec3> loop);

/// Area centroid of a planar loop [m] (vertex average for a degenerate loop).
Vec3 polygon_centroid(std::span<const Vec3> loop);

/// Largest distance of a loop's points from its best plane (through the centroid, Newell
/// normal) [m].
double planarity_error(std::span<const Vec3> loop);

/// Gathers points by index: out[i] = points[ids[i]].
template <class Ids>
std::vector<Vec3> gather(const std::vector<Vec3>& points, const Ids& ids)
{
    std::vector<Vec3> out;
    out.reserve(ids.size());
    for (auto i : ids)
        out.push_back(points[std::size_t(i)]);
    return out;
}

} // namespace polycut::geometry
