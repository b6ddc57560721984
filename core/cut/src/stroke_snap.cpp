// Rest-space snapping rules for mapped sweep triangles (see stroke_snap.hpp).
#include "stroke_snap.hpp"

#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace polycut::cut::detail {

bool snap_to_face_plane(const mesh::Mesh& m, const std::vector<Index>& near, std::array<Vec3, 3>& r,
    const std::array<bool, 3>& known, double tol, double exact, double recut_tol, double reach) {
    // Cut faces attract only a blade this close to parallel (cosine of 10 degrees): a steep
    // blade near a cut is a new cut, not the old one again.
    constexpr double kRecutCos = 0.985;
    const Vec3 blade_n = (r[1] - r[0]).cross(r[2] - r[0]).normalized();
    // The closest plane (largest corner distance) among those within their tolerance.
    double best = std::numeric_limits<double>::infinity();
    Vec3 best_n = Vec3::Zero();
    double best_d = 0;
    // The same among the Cut faces: an earlier cut's plane wins over the interior faces the
    // cutter left in that plane beyond the cut (they lie in it too).
    double best_cut = std::numeric_limits<double>::infinity();
    Vec3 cut_n = Vec3::Zero();
    double cut_d = 0;
    std::set<Index> seen;
    for (Index c : near)
        for (Index f : m.cells[std::size_t(c)].faces) {
            if (!seen.insert(f).second)
                continue;
            const std::vector<Vec3> loop = geometry::gather(m.rest, m.faces[std::size_t(f)].nodes);
            const Vec3 n = geometry::polygon_normal(loop);
            if (!(n.norm() > 0.5))
                continue;
            const double d = n.dot(geometry::polygon_centroid(loop));
            double worst = 0, nearest = std::numeric_limits<double>::infinity();
            bool fixed_ok = true, crosses = false;
            for (std::size_t k = 0; k < 3; ++k) {
                const double signed_dist = n.dot(r[k]) - d;
                const double dist = std::abs(signed_dist);
                worst = std::max(worst, dist);
                nearest = std::min(nearest, dist);
                crosses = crosses || (signed_dist > 0) != (n.dot(r[0]) - d > 0);
                fixed_ok = fixed_ok && (!known[k] || dist <= exact);
            }
            // The re-cut rule: a Cut face within recut_tol, nearly parallel to the blade, whose
            // plane the blade's meets within `reach` (it crosses it already, or converges on it at
            // a shallow angle: a wedge between the two cuts would thin to nothing). A blade
            // parallel to an earlier cut (a thin slice, 000 Fig. 9) is left where it is.
            const double sine = n.cross(blade_n).norm();
            const bool is_cut = m.faces[std::size_t(f)].tag == mesh::FaceTag::Cut;
            const bool recut = recut_tol > tol && is_cut && std::abs(n.dot(blade_n)) >= kRecutCos
                && (crosses || nearest < sine * reach);
            const double within = recut ? recut_tol : tol;
            if (!fixed_ok || !(worst <= within) || !(worst > 0))
                continue;
            if (worst <= best) {
                best = worst;
                best_n = n;
                best_d = d;
            }
            if (is_cut && worst <= best_cut) {
                best_cut = worst;
                cut_n = n;
                cut_d = d;
            }
        }
    const bool on_cut = !cut_n.isZero() && best_cut <= best + exact;
    if (on_cut) {
        best_n = cut_n;
        best_d = cut_d;
    }
    if (best_n.isZero())
        return false;
    for (std::size_t k = 0; k < 3; ++k)
        if (!known[k])
            r[k] -= (best_n.dot(r[k]) - best_d) * best_n;
    return on_cut;
}

void snap_corner_to_features(const mesh::Mesh& m, const std::vector<Index>& cells, Vec3& x,
    const Vec3& n, double d0, double tol, double in_plane) {
    double best_node = tol, best_chord = tol;
    Vec3 node_target = x, chord_target = x;
    std::vector<Vec3> ends;
    for (Index c : cells)
        for (Index f : m.cells[std::size_t(c)].faces) {
            // The chord the plane cuts from the face (an edge of it when the edge lies in the
            // plane); faces in the plane have none.
            const auto& loop = m.faces[std::size_t(f)].nodes;
            ends.clear();
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const Vec3& a = m.rest[std::size_t(loop[i])];
                const Vec3& b = m.rest[std::size_t(loop[(i + 1) % loop.size()])];
                const double da = n.dot(a) - d0, db = n.dot(b) - d0;
                if (std::abs(da) <= in_plane) {
                    ends.push_back(a);
                    if ((a - x).norm() < best_node) {
                        best_node = (a - x).norm();
                        node_target = a;
                    }
                } else if (std::abs(db) > in_plane && (da < 0) != (db < 0)) {
                    ends.push_back(a + (da / (da - db)) * (b - a));
                }
            }
            if (ends.size() != 2)
                continue;
            const Vec3 e = ends[1] - ends[0];
            if (!(e.squaredNorm() > 0))
                continue;
            const Vec3 p
                = ends[0] + std::clamp((x - ends[0]).dot(e) / e.squaredNorm(), 0.0, 1.0) * e;
            if ((p - x).norm() < best_chord) {
                best_chord = (p - x).norm();
                chord_target = p;
            }
        }
    if (best_node < tol)
        x = node_target;
    else if (best_chord < tol)
        x = chord_target;
}
} // namespace polycut::cut::detail
