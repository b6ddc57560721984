// Node snapping (002 sec. 3.2.2, Fig. 3.6): the nodes of the selected faces move onto the plane
// of the current sweep triangle in rest space. An interior node is projected orthogonally. A node
// on a flat piece of boundary is projected, for each boundary face f around it, onto the line
// plane(f) ∩ plane(sweep); the projection closest to the node that lies in f wins, so a flat
// surface keeps its shape. Going beyond 002, a node on a feature edge (two boundary planes) slides
// along that edge, and a corner node (three or more planes) stays: the boundary, hence the rest
// volume, is unchanged. A move that would leave a tet around the node inverted or flatter than
// snap_min_aspect is refused (002 sec. 3.4 suggests forbidding inverting moves).
#include "snap_state.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::cut::snap {
namespace {
Vec3 face_normal(const State& s, const std::vector<Index>& loop) {
    const Vec3 n = (s.X(loop[1]) - s.X(loop[0])).cross(s.X(loop[2]) - s.X(loop[0]));
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

bool parallel(const Vec3& a, const Vec3& b) {
    return std::abs(a.dot(b)) >= 1 - 1e-9;
}

bool in_triangle(
    const State& s, const std::vector<Index>& loop, const Vec3& n, const Vec3& w, double tol) {
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3& p = s.X(loop[k]);
        const Vec3& q = s.X(loop[(k + 1) % 3]);
        if ((q - p).cross(w - p).dot(n) < -tol * (q - p).norm())
            return false;
    }
    return true;
}

// Candidate positions of node v on the sweep plane; empty if it must stay.
std::vector<Vec3> candidates(const State& s, const SweepPlane& P, Index v, double d) {
    const Vec3 Xv = s.X(v);
    std::vector<Index> bfaces;
    for (Index c : at(s.node_cells, v))
        for (Index f : at(s.m.cells, c).faces) {
            const mesh::Face& face = at(s.m.faces, f);
            if (face.boundary()
                && std::find(face.nodes.begin(), face.nodes.end(), v) != face.nodes.end())
                bfaces.push_back(f);
        }
    if (bfaces.empty())
        return { Xv - d * P.normal };
    std::sort(bfaces.begin(), bfaces.end());
    bfaces.erase(std::unique(bfaces.begin(), bfaces.end()), bfaces.end());
    std::vector<Vec3> normals;
    std::vector<Vec3> planes; // distinct planes through v
    for (Index f : bfaces) {
        normals.push_back(face_normal(s, at(s.m.faces, f).nodes));
        if (std::none_of(planes.begin(), planes.end(),
                [&](const Vec3& q) { return parallel(q, normals.back()); }))
            planes.push_back(normals.back());
    }
    std::vector<Vec3> out;
    const double tol = 1e-9 * s.L;
    if (planes.size() == 1) {
        for (std::size_t i = 0; i < bfaces.size(); ++i) {
            const Vec3& nf = normals[i];
            const double c = nf.dot(P.normal);
            const double det = 1 - c * c;
            if (!(det > 1e-12))
                continue;
            // Closest point to Xv on both planes: Xv + alpha nf + beta n.
            const double alpha = c * d / det, beta = -d / det;
            const Vec3 w = Xv + alpha * nf + beta * P.normal;
            if (in_triangle(s, at(s.m.faces, bfaces[i]).nodes, nf, w, tol))
                out.push_back(w);
        }
    } else if (planes.size() == 2) {
        // Slide along a feature edge (v, u): an edge of two boundary faces in both planes.
        for (std::size_t i = 0; i < bfaces.size(); ++i) {
            const auto& loop = at(s.m.faces, bfaces[i]).nodes;
            for (Index u : loop) {
                if (u == v)
                    continue;
                bool feature = false;
                for (std::size_t j = 0; j < bfaces.size(); ++j) {
                    const auto& l2 = at(s.m.faces, bfaces[j]).nodes;
                    if (j != i && std::find(l2.begin(), l2.end(), u) != l2.end()
                        && !parallel(normals[i], normals[j]))
                        feature = true;
                }
                if (!feature)
                    continue;
                const double du = P.distance(s.X(u));
                if (d * du > 0 || d == du)
                    continue;
                const double t = d / (d - du);
                out.push_back(Xv + t * (s.X(u) - Xv));
            }
        }
    }
    return out;
}
} // namespace

std::vector<Index> snap_face_nodes(State& s, const SweepPlane& P, const std::vector<Index>& faces) {
    std::vector<Index> nodes;
    for (Index f : faces)
        for (Index n : at(s.m.faces, f).nodes)
            nodes.push_back(n);
    return snap_nodes(s, P, std::move(nodes));
}

std::vector<Index> snap_nodes(State& s, const SweepPlane& P, std::vector<Index> nodes) {
    std::vector<Index> moved;
    const double eps = s.opt.plane_eps * s.L;
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (Index v : nodes) {
        const double d = P.distance(s.X(v));
        if (std::abs(d) <= eps)
            continue;
        const auto cand = candidates(s, P, v, d);
        if (cand.empty())
            continue;
        const Vec3* best = nullptr;
        for (const Vec3& w : cand)
            if (!best || (w - s.X(v)).norm() < (*best - s.X(v)).norm())
                best = &w;
        bool ok = true;
        for (Index c : at(s.node_cells, v))
            ok = ok && s.aspect(c, v, *best) >= std::max(s.opt.snap_min_aspect, 1e-12);
        if (!ok) {
            ++s.stats.snaps_refused;
            continue;
        }
        s.move_node(v, *best);
        moved.push_back(v);
        ++s.stats.nodes_snapped;
    }
    return moved;
}

} // namespace polycut::cut::snap
