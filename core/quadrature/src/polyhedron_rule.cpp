#include "polycut/quadrature/polyhedron_rule.hpp"

#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/quadrature/tet_rules.hpp"

namespace polycut::quadrature {
namespace {
void append_tet(const std::vector<BaryPoint>& ref, const Vec3& a, const Vec3& b, const Vec3& c,
    const Vec3& d, std::vector<QuadPoint>& out) {
    const double vol = (b - a).dot((c - a).cross(d - a)) / 6.0;
    if (vol == 0.0)
        return;
    for (const BaryPoint& p : ref)
        out.push_back(
            { p.bary[0] * a + p.bary[1] * b + p.bary[2] * c + p.bary[3] * d, p.weight * vol });
}
} // namespace

std::vector<QuadPoint> rule_on_tet(
    const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int degree) {
    std::vector<QuadPoint> out;
    append_tet(tet_rule(degree), a, b, c, d, out);
    return out;
}

std::vector<QuadPoint> rule_on_polyhedron(
    const std::vector<Vec3>& points, const std::vector<std::vector<Index>>& loops, int degree) {
    const std::vector<BaryPoint> ref = tet_rule(degree);
    const Vec3 cell_c = geometry::polyhedron_centroid(points, loops);
    std::vector<QuadPoint> out;
    for (const auto& loop : loops) {
        const std::vector<Vec3> P = geometry::gather(points, loop);
        const Vec3 face_c = geometry::polygon_centroid(P);
        for (std::size_t i = 0; i < P.size(); ++i) {
            const Vec3& p = P[i];
            const Vec3& q = P[(i + 1) % P.size()];
            // (p, q, face_c) is counter-clockwise seen from outside, so (cell_c, p, q, face_c)
            // has positive volume when cell_c is inside.
            append_tet(ref, cell_c, p, q, face_c, out);
        }
    }
    return out;
}

} // namespace polycut::quadrature
