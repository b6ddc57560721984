#include "polycut/geometry/polyhedron.hpp"

#include "polycut/geometry/polygon.hpp"

#include <cmath>
#include <numbers>

namespace polycut::geometry {
namespace {
// Fan-triangulates each loop around its vertex mean (exact for planar loops) and calls
// visit(a, b, c) per triangle.
template <class Visit>
void for_each_triangle(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, Visit&& visit) {
    for (const auto& loop : loops) {
        Vec3 m = Vec3::Zero();
        for (Index i : loop)
            m += points[std::size_t(i)];
        m /= double(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i)
            visit(
                m, points[std::size_t(loop[i])], points[std::size_t(loop[(i + 1) % loop.size()])]);
    }
}
} // namespace

double polyhedron_volume(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops) {
    double v = 0;
    for_each_triangle(points, loops,
        [&](const Vec3& a, const Vec3& b, const Vec3& c) { v += a.dot(b.cross(c)); });
    return v / 6.0;
}

Vec3 polyhedron_centroid(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops) {
    // Tetrahedra from an interior reference point (vertex mean) to each surface triangle.
    Vec3 ref = Vec3::Zero();
    std::size_t n = 0;
    for (const auto& loop : loops)
        for (Index i : loop) {
            ref += points[std::size_t(i)];
            ++n;
        }
    ref /= double(std::max<std::size_t>(n, 1));
    double vol = 0;
    Vec3 c = Vec3::Zero();
    for_each_triangle(points, loops, [&](const Vec3& a, const Vec3& b, const Vec3& d) {
        const double v = (a - ref).dot((b - ref).cross(d - ref)) / 6.0;
        vol += v;
        c += v * (ref + a + b + d) / 4.0;
    });
    return vol != 0 ? Vec3(c / vol) : ref;
}

bool polyhedron_is_convex(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, double tol) {
    Aabb box;
    for (const auto& loop : loops)
        for (Index i : loop)
            box.extend(points[std::size_t(i)]);
    const double eps = tol * box.diagonal();
    for (const auto& loop : loops) {
        const auto face = gather(points, loop);
        const Vec3 n = polygon_normal(face);
        const Vec3 c = polygon_centroid(face);
        for (const auto& other : loops)
            for (Index i : other)
                if ((points[std::size_t(i)] - c).dot(n) > eps)
                    return false;
    }
    return true;
}

double polyhedron_winding(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, const Vec3& x) {
    double omega = 0;
    for_each_triangle(points, loops, [&](const Vec3& pa, const Vec3& pb, const Vec3& pc) {
        const Vec3 a = pa - x, b = pb - x, c = pc - x;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        omega += 2
            * std::atan2(
                a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
    });
    return omega / (4 * std::numbers::pi);
}

} // namespace polycut::geometry
