// Local cell geometry and the orientation-independent fan triangulation of its faces.
#include "polycut/basis/cell_geometry.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <limits>
#include <unordered_map>

namespace polycut::basis {

CellGeometry cell_geometry(const mesh::Mesh& mesh, Index cell) {
    const auto& c = mesh.cells[std::size_t(cell)];
    CellGeometry out;
    std::unordered_map<Index, Index> local;
    out.nodes.reserve(c.nodes.size());
    for (std::size_t i = 0; i < c.nodes.size(); ++i) {
        local.emplace(c.nodes[i], Index(i));
        out.nodes.push_back(mesh.rest[std::size_t(c.nodes[i])]);
    }
    for (std::size_t k = 0; k < c.faces.size(); ++k) {
        auto loop = mesh.face_loop(c.faces[k], cell);
        for (auto& v : loop) {
            auto it = local.find(v);
            if (it == local.end())
                throw MeshError(cell, c.faces[k], "face node is not a node of the cell");
            v = it->second;
        }
        out.loops.push_back(std::move(loop));
    }
    return out;
}

double cell_size(const std::vector<Vec3>& nodes) {
    geometry::Aabb box;
    for (const auto& p : nodes)
        box.extend(p);
    return box.diagonal();
}

std::vector<SurfaceTriangle> fan_triangulation(
    const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops, double area_tol) {
    std::vector<SurfaceTriangle> tris;
    for (std::size_t f = 0; f < loops.size(); ++f) {
        const auto& loop = loops[f];
        const std::size_t k = loop.size();
        if (k < 3)
            continue;
        const auto pts = geometry::gather(nodes, loop);
        const Vec3 normal = geometry::polygon_normal(pts);
        // Score of apex a: the smallest triangle area of its fan (-1 if a fan triangle is
        // inverted relative to the face normal). It depends on the triangle set only and is
        // bit-identical for both orientations of the loop; near-ties go to the lexicographically
        // smallest apex position, so both cells sharing the face pick the same apex.
        std::vector<double> scores(k);
        for (std::size_t a = 0; a < k; ++a) {
            double score = std::numeric_limits<double>::infinity();
            for (std::size_t s = 1; s + 1 < k; ++s) {
                const Vec3& p = pts[a];
                const Vec3 cr = (pts[(a + s) % k] - p).cross(pts[(a + s + 1) % k] - p);
                score = std::min(score, 0.5 * cr.norm());
                if (cr.dot(normal) < -2.0 * area_tol)
                    score = -1.0;
            }
            scores[a] = score;
        }
        double top = -std::numeric_limits<double>::infinity();
        for (double sc : scores)
            top = std::max(top, sc);
        std::size_t best = k;
        for (std::size_t a = 0; a < k; ++a) {
            if (scores[a] < top - 1e-9 * std::abs(top))
                continue;
            if (best == k
                || std::lexicographical_compare(
                    pts[a].data(), pts[a].data() + 3, pts[best].data(), pts[best].data() + 3))
                best = a;
        }
        for (std::size_t s = 1; s + 1 < k; ++s) {
            const Index i = loop[best], j = loop[(best + s) % k], l = loop[(best + s + 1) % k];
            const Vec3 cr = (nodes[std::size_t(j)] - nodes[std::size_t(i)])
                                .cross(nodes[std::size_t(l)] - nodes[std::size_t(i)]);
            if (0.5 * cr.norm() <= area_tol)
                continue;
            tris.push_back(SurfaceTriangle { { i, j, l }, Index(f) });
        }
    }
    return tris;
}

} // namespace polycut::basis
