// Coarsening of sweep strips (sweep_strip.hpp). A `cut` request that carries a stroke sampled
// finer than the mesh resolves re-splits the same cells once per sample: on the default block
// a 500-triangle quarter circle (0.5 mm per sample, 1 cm cells) made cells of ~100 face corners
// and cuts of 350 ms per tick. Samples closer than a quarter cell are what the server already
// holds back for `scalpel` notifications; the same rule here makes both paths cut alike.
#include "sweep_strip.hpp"

#include <algorithm>

namespace polycut::cut::detail {
namespace {

// Whether triangles t, u form the quad of samples (a0, b0) -> (a1, b1) in the scalpel's order.
bool is_quad(const Triangle& t, const Triangle& u) {
    return u[0] == t[1] && u[2] == t[2] && t[0] != t[1] && t[2] != u[1];
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double dd = d.squaredNorm();
    const double s = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (p - (a + s * d)).norm();
}

} // namespace

CoarseSweep coarsen_strips(std::span<const Triangle> tris, double min_advance, double tolerance) {
    CoarseSweep out;
    out.triangles.reserve(tris.size());
    out.first.reserve(tris.size());
    out.may_stop.reserve(tris.size());
    std::size_t i = 0;
    while (i < tris.size()) {
        // The samples of a run of quads starting at triangle i: (a_k, b_k), k = 0..m.
        std::vector<Vec3> a, b;
        std::size_t j = i;
        while (min_advance > 0 && j + 1 < tris.size() && is_quad(tris[j], tris[j + 1])
            && (a.empty() || (tris[j][0] == a.back() && tris[j][1] == b.back()))) {
            if (a.empty()) {
                a.push_back(tris[j][0]);
                b.push_back(tris[j][1]);
            }
            a.push_back(tris[j][2]);
            b.push_back(tris[j + 1][1]);
            j += 2;
        }
        const std::size_t m = a.empty() ? 0 : a.size() - 1; // quads in the run
        if (m < 2) {
            // Not a run of two quads or more: the triangle as it came.
            out.triangles.push_back(tris[i]);
            out.first.push_back(i);
            out.may_stop.push_back(1);
            ++i;
            continue;
        }
        // Every dropped sample between kept samples l and e within tolerance of the edges.
        const auto within = [&](std::size_t l, std::size_t e) {
            for (std::size_t k = l + 1; k < e; ++k)
                if (distance_to_segment(a[k], a[l], a[e]) > tolerance
                    || distance_to_segment(b[k], b[l], b[e]) > tolerance)
                    return false;
            return true;
        };
        std::vector<std::size_t> kept { 0 };
        for (std::size_t k = 1; k <= m; ++k) {
            const std::size_t l = kept.back();
            const double advance = std::max((a[k] - a[l]).norm(), (b[k] - b[l]).norm());
            if (k == m || advance >= min_advance || !within(l, k + 1))
                kept.push_back(k);
        }
        for (std::size_t q = 0; q + 1 < kept.size(); ++q) {
            const std::size_t l = kept[q], e = kept[q + 1];
            out.triangles.push_back({ a[l], b[l], a[e] });
            out.triangles.push_back({ b[l], b[e], a[e] });
            out.first.push_back(i + 2 * l);
            out.first.push_back(i + 2 * l);
            out.may_stop.push_back(0);
            out.may_stop.push_back(1);
        }
        i = j;
    }
    return out;
}

} // namespace polycut::cut::detail
