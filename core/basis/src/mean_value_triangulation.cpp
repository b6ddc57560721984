// Triangulation of the polygonal faces of a mean value cell (seed 000 sec. 3.2 defines the
// coordinates on a triangulated surface but leaves the triangulation open).
//
// Choice: the Delaunay triangulation of each (convex) face loop. A fan from one vertex joins that
// vertex to every other vertex of the face: on the many-sided faces a plane split makes (5-8
// vertices, some on straight edges) it is a spread of needle triangles, and both the mean value
// basis and the face samples of 000 eq. 15-16 inherit them (the apex's function reaches across
// the whole face, the face samples crowd at the apex). The Delaunay triangulation maximizes the
// smallest angle, keeps each function local to the vertices near it, and never makes a sliver
// the face does not force (nearly collinear vertices along a crack front stay out of thin
// triangles: slivers make the gradients, and so Ke, badly conditioned). For points in convex
// position it is built chord by chord: the triangle on chord (i, j) takes the vertex between them
// that sees the chord under the largest angle (its circumcircle holds no other vertex of that
// side), O(k^2) per face. Measured on the 002 sec. 3.3 cantilever on one-plane-split blocks
// (docs/perf.md): tip error at 1,743 nodes -9.95 % -> -7.9 % (heuristic rule), -7.60 % -> -5.8 %
// (reference rule). (The minimum-weight triangulation, least total diagonal length, does as well
// on the cantilever but makes slivers on cut faces: PCG stalled on cut_pencil.)
//
// C0 across cells: the two cells sharing a face see the same loop, in opposite orientations and
// possibly from a different first vertex. The loop is first put in a canonical order that depends
// on its vertex positions only (start at the lexicographically smallest position, a strict
// corner; go towards the lexicographically smaller neighbour), so the construction runs on
// bit-identical input in both cells and picks the same triangles (ties to the first vertex in
// that order); the triangles are then oriented as the cell's loop.
#include "polycut/basis/mean_value.hpp"
#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace polycut::basis {
namespace {
bool lex_less(const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}
} // namespace

std::vector<SurfaceTriangle> mean_value_triangulation(
    const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops, double area_tol) {
    std::vector<SurfaceTriangle> tris;
    std::vector<Index> c;
    std::vector<std::pair<std::size_t, std::size_t>> todo;
    for (std::size_t f = 0; f < loops.size(); ++f) {
        const auto& loop = loops[f];
        const std::size_t k = loop.size();
        if (k < 3)
            continue;
        auto at = [&](std::size_t i) -> const Vec3& { return nodes[std::size_t(loop[i % k])]; };
        std::size_t s = 0;
        for (std::size_t i = 1; i < k; ++i)
            if (lex_less(at(i), at(s)))
                s = i;
        const bool reversed = lex_less(at(s + k - 1), at(s + 1));
        c.resize(k);
        for (std::size_t i = 0; i < k; ++i)
            c[i] = loop[reversed ? (s + k - i) % k : (s + i) % k];
        auto P = [&](std::size_t i) -> const Vec3& { return nodes[std::size_t(c[i])]; };
        const Vec3 normal = geometry::polygon_normal(geometry::gather(nodes, c));
        todo.assign(1, { 0, k - 1 });
        while (!todo.empty()) {
            const auto [i, j] = todo.back();
            todo.pop_back();
            if (j < i + 2)
                continue;
            // apex: a proper (positive-area, outward) triangle first, then the largest angle
            std::size_t m = j;
            bool m_ok = false;
            double m_angle = -1;
            for (std::size_t v = i + 1; v < j; ++v) {
                const Vec3 a = P(i) - P(v), b = P(j) - P(v);
                const Vec3 cr = b.cross(a); // (i, v, j) in loop order: (v - i) x (j - i)
                const bool ok = 0.5 * cr.dot(normal) > area_tol;
                const double angle = std::atan2(cr.norm(), a.dot(b));
                if ((ok && !m_ok) || (ok == m_ok && angle > m_angle)) {
                    m = v;
                    m_ok = ok;
                    m_angle = angle;
                }
            }
            // zero-area triangles (collinear vertices) add nothing to the mean value weights
            if (0.5 * (P(m) - P(i)).cross(P(j) - P(i)).norm() > area_tol)
                tris.push_back(reversed ? SurfaceTriangle { { c[i], c[j], c[m] }, Index(f) }
                                        : SurfaceTriangle { { c[i], c[m], c[j] }, Index(f) });
            todo.push_back({ i, m });
            todo.push_back({ m, j });
        }
    }
    return tris;
}

} // namespace polycut::basis
