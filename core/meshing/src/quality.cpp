// Dihedral angles and radius ratios of the tets of a mesh (no CGAL: any tet mesh can be measured,
// whichever geometry produced it).
#include "polycut/meshing/quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace polycut::meshing {

namespace {

struct TetShape {
    double min_dihedral = 0; ///< [rad]
    double max_dihedral = 0; ///< [rad]
    double radius_ratio = 0; ///< 3 r_in / r_circ
};

TetShape measure(const std::array<Vec3, 4>& p) {
    TetShape s;
    const Vec3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
    const double six_volume = std::abs(a.dot(b.cross(c)));
    // Area vectors of the faces opposite each vertex, all outward or all inward (the angle
    // between two of them does not depend on which).
    std::array<Vec3, 4> n;
    for (int k = 0; k < 4; ++k) {
        const Vec3& q0 = p[std::size_t((k + 1) % 4)];
        const Vec3& q1 = p[std::size_t((k + 2) % 4)];
        const Vec3& q2 = p[std::size_t((k + 3) % 4)];
        n[std::size_t(k)] = (q1 - q0).cross(q2 - q0);
        // Orient away from the opposite vertex.
        if (n[std::size_t(k)].dot(q0 - p[std::size_t(k)]) < 0)
            n[std::size_t(k)] = -n[std::size_t(k)];
    }
    double area_sum = 0;
    for (const Vec3& v : n)
        area_sum += 0.5 * v.norm();
    if (!(six_volume > 0) || !(area_sum > 0))
        return s; // flat or collapsed: angle 0, ratio 0
    s.min_dihedral = std::numbers::pi;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
            // The faces opposite vertices i and j meet along the edge joining the other two; the
            // dihedral angle is pi minus the angle between their outward normals.
            const Vec3& ni = n[std::size_t(i)];
            const Vec3& nj = n[std::size_t(j)];
            const double cos_normals = std::clamp(ni.dot(nj) / (ni.norm() * nj.norm()), -1.0, 1.0);
            const double angle = std::numbers::pi - std::acos(cos_normals);
            s.min_dihedral = std::min(s.min_dihedral, angle);
            s.max_dihedral = std::max(s.max_dihedral, angle);
        }
    // r_in = 3 V / A; circumcentre offset from p0 = (|a|^2 b x c + |b|^2 c x a + |c|^2 a x b)
    // / (2 a . (b x c)).
    const double r_in = 0.5 * six_volume / area_sum;
    const Vec3 offset = (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a)
                            + c.squaredNorm() * a.cross(b))
        / (2 * a.dot(b.cross(c)));
    const double r_circ = offset.norm();
    s.radius_ratio = r_circ > 0 ? std::min(1.0, 3 * r_in / r_circ) : 0;
    return s;
}

/// Nearest-rank quantile q in [0, 1] of `values` (reordered).
double quantile(std::vector<double>& values, double q) {
    const auto k = std::size_t(std::floor(q * double(values.size() - 1)));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

} // namespace

TetQuality tet_quality(const mesh::Mesh& m) {
    TetQuality q;
    std::vector<double> ratios;
    ratios.reserve(m.cells.size());
    double min_angle = std::numbers::pi, max_angle = 0;
    const double sliver = kSliverDihedralDeg * std::numbers::pi / 180;
    for (const mesh::Cell& cell : m.cells) {
        if (cell.shape != mesh::CellShape::Tet || cell.nodes.size() != 4)
            continue;
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k)
            p[k] = m.rest[std::size_t(cell.nodes[k])];
        const TetShape s = measure(p);
        min_angle = std::min(min_angle, s.min_dihedral);
        max_angle = std::max(max_angle, s.max_dihedral);
        ratios.push_back(s.radius_ratio);
        if (s.min_dihedral < sliver)
            ++q.slivers;
    }
    q.tets = Index(ratios.size());
    if (ratios.empty())
        return q;
    const double deg = 180 / std::numbers::pi;
    q.min_dihedral_deg = min_angle * deg;
    q.max_dihedral_deg = max_angle * deg;
    q.radius_ratio_min = *std::min_element(ratios.begin(), ratios.end());
    q.radius_ratio_p1 = quantile(ratios, 0.01);
    q.radius_ratio_p50 = quantile(ratios, 0.5);
    return q;
}

std::string to_string(const TetQuality& q) {
    char line[256];
    std::snprintf(line, sizeof line,
        "%d tets, dihedral %.1f-%.1f deg, radius ratio min %.3f p1 %.3f p50 %.3f, %d slivers "
        "(< %.0f deg)%s",
        q.tets, q.min_dihedral_deg, q.max_dihedral_deg, q.radius_ratio_min, q.radius_ratio_p1,
        q.radius_ratio_p50, q.slivers, kSliverDihedralDeg,
        q.has_slivers() ? ": WARNING, slivers" : "");
    return line;
}

} // namespace polycut::meshing
