// Triangulation of the polygonal faces of a mean value cell (seed 000 sec. 3.2 defines the
// coordinates on a triangulated surface but leaves the triangulation open).
//
// Choice: the minimum-weight triangulation of each (convex) face loop, the one with the smallest
// total edge length, found by the O(k^3) dynamic program over the loop's vertices. A fan from one
// vertex joins that vertex to every other vertex of the face: on the many-sided faces a plane
// split makes (5-8 vertices, some on straight edges) it is a spread of needle triangles, and both
// the mean value basis and the face samples of 000 eq. 15-16 inherit them (the apex's function
// reaches across the whole face, the face samples crowd at the apex). Short diagonals keep each
// function local to the vertices near it. Measured on the 002 sec. 3.3 cantilever on one-plane-
// split blocks (docs/perf.md): tip error -9.95 % -> -7.68 % (heuristic rule) and -7.60 % ->
// -5.52 % (reference rule) at 1,743 nodes; the max-min-angle (Delaunay-like) triangulation gives
// nearly the same (-7.87 / -5.75 %).
//
// C0 across cells: the two cells sharing a face see the same loop, in opposite orientations and
// possibly from a different first vertex. The loop is first put in a canonical order that depends
// on its vertex positions only (start at the lexicographically smallest position; go towards the
// lexicographically smaller neighbour), so the program runs on bit-identical input in both cells
// and picks the same diagonals; the triangles are then oriented as the cell's loop.
#include "polycut/basis/mean_value.hpp"
#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace polycut::basis {
namespace {
bool lex_less(const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

/// Cost of a (partial) triangulation: triangles that are degenerate (collinear vertices) or
/// inverted count first, total edge length second.
struct Cost {
    int bad = 0;
    double length = 0;
    bool operator<(const Cost& o) const { return bad != o.bad ? bad < o.bad : length < o.length; }
    Cost operator+(const Cost& o) const { return { bad + o.bad, length + o.length }; }
};
} // namespace

std::vector<SurfaceTriangle> mean_value_triangulation(
    const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops, double area_tol) {
    std::vector<SurfaceTriangle> tris;
    std::vector<Index> c;
    std::vector<Cost> best;
    std::vector<std::size_t> split;
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
        auto chord = [&](std::size_t i, std::size_t j) {
            // boundary edges are in every triangulation: only diagonals count
            return j == i + 1 || (i == 0 && j == k - 1) ? 0.0 : (P(j) - P(i)).norm();
        };
        // best[i * k + j]: cheapest triangulation of the sub-polygon i..j (i < j), closed by
        // the chord (i, j); split[]: its apex m, the triangle (i, m, j).
        best.assign(k * k, Cost {});
        split.assign(k * k, k);
        for (std::size_t len = 2; len < k; ++len)
            for (std::size_t i = 0; i + len < k; ++i) {
                const std::size_t j = i + len;
                Cost top { std::numeric_limits<int>::max(), 0.0 };
                for (std::size_t m = i + 1; m < j; ++m) {
                    const Vec3 cr = (P(m) - P(i)).cross(P(j) - P(i));
                    Cost t { 0.5 * cr.dot(normal) > area_tol ? 0 : 1, chord(i, m) + chord(m, j) };
                    t = t + best[i * k + m] + best[m * k + j];
                    if (t < top) { // strict: the first apex wins ties, same in both cells
                        top = t;
                        split[i * k + j] = m;
                    }
                }
                best[i * k + j] = top;
            }
        std::vector<std::pair<std::size_t, std::size_t>> todo { { 0, k - 1 } };
        while (!todo.empty()) {
            const auto [i, j] = todo.back();
            todo.pop_back();
            if (j < i + 2)
                continue;
            const std::size_t m = split[i * k + j];
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
