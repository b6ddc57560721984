// Coarsening behind a progressive cut. Every tick's sweep triangles clip the faces in the cut
// plane along their edges, so the crack's faces and lips collect a node at every earlier front
// position. Once a node lies strictly inside a straight edge in every face that uses it (its two
// loop neighbours and it are collinear, it between them), it shapes nothing: removing it from all
// those loops leaves every face polygon, every cell, the volume and the surface exactly as they
// were, and takes its three DOFs out of the system. Crack-front corners, polygon vertices and
// T-junction corners turn in some face and stay.
#include "polycut/geometry/polygon.hpp"
#include "sweep.hpp"

#include <algorithm>

namespace polycut::cut::detail {
namespace {
// True when x lies strictly between a and b on their segment, up to tol [m].
bool inside_segment(const Vec3& a, const Vec3& x, const Vec3& b, double tol) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    if (!(len2 > 0))
        return false;
    const double t = (x - a).dot(ab) / len2;
    if (!(t > 0 && t < 1))
        return false;
    return (a + t * ab - x).norm() <= tol;
}
} // namespace

Index remove_collinear_nodes(Editor& ed, const std::vector<Index>& cells) {
    mesh::Mesh& m = ed.m;
    std::vector<Index> nodes;
    for (Index c : cells)
        nodes.insert(nodes.end(), at(m.cells, c).nodes.begin(), at(m.cells, c).nodes.end());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    Index removed = 0;
    std::vector<Index> faces;
    for (Index n : nodes) {
        const std::vector<Index> around = at(ed.node_cells, n);
        if (around.empty())
            continue;
        faces.clear();
        double tol = 0;
        for (Index c : around) {
            tol = std::max(tol, 1e-9 * ed.bounds(c).diagonal());
            for (Index f : at(m.cells, c).faces)
                if (find_in(at(m.faces, f).nodes, n) >= 0)
                    faces.push_back(f);
        }
        std::sort(faces.begin(), faces.end());
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
        bool straight = !faces.empty();
        for (Index f : faces) {
            const auto& loop = at(m.faces, f).nodes;
            const std::size_t k = loop.size();
            const int i = find_in(loop, n);
            const Index u = loop[(std::size_t(i) + k - 1) % k], w = loop[(std::size_t(i) + 1) % k];
            // A face that is not planar (a snapped node kept a few micrometres off a crack's
            // plane) keeps its nodes: dropping one moves the centre the face's volume is
            // measured from, and the rest volume would change.
            straight = straight && k > 3
                && inside_segment(at(m.rest, u), at(m.rest, n), at(m.rest, w), tol)
                && geometry::planarity_error(geometry::gather(m.rest, loop)) <= tol;
            if (!straight)
                break;
        }
        if (!straight)
            continue;
        // If some other face joins the same two neighbours (the duplicate of n on the other
        // lip of a crack, a face spanning u..w), removing n would pinch the edge u-w between the
        // two sides of the crack: keep it (fix_pinched_edges put it there for that reason).
        const auto& l0 = at(m.faces, faces.front()).nodes;
        const int i0 = find_in(l0, n);
        const Index u = l0[(std::size_t(i0) + l0.size() - 1) % l0.size()];
        const Index w = l0[(std::size_t(i0) + 1) % l0.size()];
        bool other_path = false;
        for (Index c : at(ed.node_cells, u))
            for (Index f : at(m.cells, c).faces)
                if (!std::binary_search(faces.begin(), faces.end(), f)
                    && find_in(at(m.faces, f).nodes, u) >= 0
                    && find_in(at(m.faces, f).nodes, w) >= 0)
                    other_path = true;
        if (other_path)
            continue;
        for (Index f : faces) {
            auto& loop = at(m.faces, f).nodes;
            loop.erase(loop.begin() + find_in(loop, n));
        }
        for (Index c : around)
            ed.refresh_cell_nodes(c);
        ++removed;
    }
    return removed;
}

} // namespace polycut::cut::detail
