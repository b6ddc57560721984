// Polyhedra given as face loops (outward orientation): volume, centroid, convexity, and
// axis-aligned boxes.
#pragma once

#include "polycut/common/types.hpp"

#include <span>

namespace polycut::geometry {

/// A polyhedron as loops of point indices into an external point array, each loop oriented
/// outward (right-hand rule).
struct FaceLoops {
    const std::vector<Vec3>* points = nullptr;
    std::vector<std::span<const Index>> loops;
};

/// Signed volume by the divergence theorem [m^3]; positive for outward loops.
double polyhedron_volume(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops);

/// Volume centroid [m].
Vec3 polyhedron_centroid(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops);

/// True when every vertex lies on the inner side of every face plane, up to tol * size.
bool polyhedron_is_convex(const std::vector<Vec3>& points,
    const std::vector<std::vector<Index>>& loops, double tol = 1e-9);

/// Winding number of the closed polyhedron about point x: the sum of the signed solid angles
/// of its faces (fans about each loop's vertex mean; van Oosterom and Strackee 1983) over
/// 4 pi. 1 inside, 0 outside, fractional only on the boundary; for non-convex cells too.
double polyhedron_winding(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, const Vec3& x);

/// Axis-aligned bounding box.
struct Aabb {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
    void extend(const Vec3& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    void extend(const Aabb& b) {
        lo = lo.cwiseMin(b.lo);
        hi = hi.cwiseMax(b.hi);
    }
    bool empty() const { return (lo.array() > hi.array()).any(); }
    bool overlaps(const Aabb& b) const {
        return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all();
    }
    Vec3 center() const { return 0.5 * (lo + hi); }
    Vec3 extent() const { return hi - lo; }
    double diagonal() const { return empty() ? 0.0 : (hi - lo).norm(); }
};

} // namespace polycut::geometry
