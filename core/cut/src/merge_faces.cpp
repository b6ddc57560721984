// Merging coplanar Cut faces of a cell. Each tick of a progressive cut clips the faces in the
// crack plane along the sweep triangles' edges, so the crack side of a cell becomes a strip of
// small Cut faces in one plane, and the corners of every strip stay in the mesh (coarsening can
// only drop a node that lies inside a straight edge of every face using it). Two Cut faces of one
// cell that lie in one plane and share a chain of edges are replaced by their union, a convex
// polygon with the same vertices minus the chain's interior; the chain's end nodes then lie on
// straight edges and coarsening removes them. No node moves and every vertex of the union is a
// vertex of one of the two planar faces, so the volume, the boundary surface and the planarity
// stay as they were up to round-off.
#include "polycut/geometry/polygon.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace polycut::cut::detail {
namespace {

// Coplanarity: every vertex of each face within kPlaneTol x (cell bounding-box diagonal) of the
// other face's plane, and the unit normals parallel to within kAngleTol [rad], same direction.
// Both are round-off scale: the simulation puts a straight stroke exactly in one rest plane
// (core/sim kStrokePlane projects every tick onto it), so its faces agree to ~1e-15 x L; faces
// of a bent stroke or of a cell's other sides differ by far more. A loose tolerance would make
// the merged face non-planar, which the volume and closedness invariants would not survive.
constexpr double kPlaneTol = 1e-9;
constexpr double kAngleTol = 1e-7;
// Convexity of the union: at each vertex the turn may be negative by at most this sine (collinear
// vertices within round-off are kept and coarsened afterwards).
constexpr double kTurnTol = 1e-9;

bool is_cut_boundary(const mesh::Face& f) {
    return f.tag == mesh::FaceTag::Cut && f.boundary();
}

// Union loop of faces f and g (outward loops of the same cell) when they share exactly one chain
// of edges and no other vertex; empty otherwise. `inner` receives the chain's interior nodes.
std::vector<Index> union_loop(
    const std::vector<Index>& f, const std::vector<Index>& g, std::vector<Index>& inner) {
    const std::size_t kf = f.size(), kg = g.size();
    // Edge i of f (f[i] -> f[i+1]) is shared if g has f[i+1] -> f[i].
    auto shared = [&](std::size_t i) {
        const Index u = f[i], v = f[(i + 1) % kf];
        const int j = find_in(g, v);
        return j >= 0 && g[(std::size_t(j) + 1) % kg] == u;
    };
    std::vector<char> s(kf);
    std::size_t count = 0;
    for (std::size_t i = 0; i < kf; ++i)
        count += (s[i] = shared(i)) ? 1 : 0;
    if (count == 0 || count >= kf || count >= kg)
        return {};
    // Start of the chain: a shared edge whose predecessor is not shared; exactly one.
    std::size_t start = kf, starts = 0;
    for (std::size_t i = 0; i < kf; ++i)
        if (s[i] && !s[(i + kf - 1) % kf]) {
            start = i;
            ++starts;
        }
    if (starts != 1)
        return {};
    // Chain vertices f[start] ... f[start + count] (count edges).
    const std::size_t end = (start + count) % kf;
    inner.clear();
    for (std::size_t k = 1; k < count; ++k)
        inner.push_back(f[(start + k) % kf]);
    // No vertex other than the chain's may be common to f and g (the union would touch itself).
    std::size_t common = 0;
    for (Index v : f)
        common += find_in(g, v) >= 0 ? 1 : 0;
    if (common != count + 1)
        return {};
    // f from the chain's end around to its start, then g from after the start to before the end.
    std::vector<Index> out;
    for (std::size_t i = end;; i = (i + 1) % kf) {
        out.push_back(f[i]);
        if (i == start)
            break;
    }
    const std::size_t gs = std::size_t(find_in(g, f[start]));
    const std::size_t ge = std::size_t(find_in(g, f[end]));
    for (std::size_t j = (gs + 1) % kg; j != ge; j = (j + 1) % kg)
        out.push_back(g[j]);
    return out;
}

// Whether the loop is a convex polygon turning once around normal n (collinear runs allowed).
bool convex_loop(const std::vector<Vec3>& p, const Vec3& n) {
    const std::size_t k = p.size();
    double turning = 0;
    for (std::size_t i = 0; i < k; ++i) {
        const Vec3 a = p[(i + k - 1) % k], b = p[i], c = p[(i + 1) % k];
        const Vec3 e0 = b - a, e1 = c - b;
        const double l0 = e0.norm(), l1 = e1.norm();
        if (!(l0 > 0) || !(l1 > 0))
            return false;
        const double sine = e0.cross(e1).dot(n) / (l0 * l1);
        if (sine < -kTurnTol)
            return false;
        turning += std::atan2(sine, e0.dot(e1) / (l0 * l1));
    }
    return std::abs(turning - 2 * std::numbers::pi) < 1e-6;
}

// Whether every vertex of `pts` lies within tol of the plane (n, c).
bool on_plane(const std::vector<Vec3>& pts, const Vec3& n, const Vec3& c, double tol) {
    for (const Vec3& x : pts)
        if (std::abs((x - c).dot(n)) > tol)
            return false;
    return true;
}

// Whether node v is used by a face other than f and g (in any cell around it).
bool used_elsewhere(const Editor& ed, Index v, Index f, Index g) {
    for (Index c : at(ed.node_cells, v))
        for (Index h : at(ed.m.cells, c).faces)
            if (h != f && h != g && find_in(at(ed.m.faces, h).nodes, v) >= 0)
                return true;
    return false;
}

// Tries to merge face g into face f (both Cut boundary faces of cell c). Returns success.
bool try_merge(Editor& ed, Index c, Index f, Index g) {
    mesh::Mesh& m = ed.m;
    const auto& lf = at(m.faces, f).nodes;
    const auto& lg = at(m.faces, g).nodes;
    std::vector<Index> inner;
    std::vector<Index> loop = union_loop(lf, lg, inner);
    if (loop.size() < 3)
        return false;
    const auto pf = geometry::gather(m.rest, lf), pg = geometry::gather(m.rest, lg);
    const Vec3 nf = geometry::polygon_normal(pf), ng = geometry::polygon_normal(pg);
    if (!(nf.dot(ng) > 0) || nf.cross(ng).norm() > kAngleTol)
        return false;
    const double tol = kPlaneTol * ed.bounds(c).diagonal();
    if (!on_plane(pg, nf, geometry::polygon_centroid(pf), tol)
        || !on_plane(pf, ng, geometry::polygon_centroid(pg), tol))
        return false;
    const auto pu = geometry::gather(m.rest, loop);
    if (!convex_loop(pu, nf))
        return false;
    const double af = geometry::polygon_area(pf), ag = geometry::polygon_area(pg);
    if (std::abs(geometry::polygon_area(pu) - (af + ag)) > 1e-9 * (af + ag))
        return false;
    for (Index v : inner)
        if (used_elsewhere(ed, v, f, g))
            return false;
    at(m.faces, f).nodes = std::move(loop);
    auto& faces = at(m.cells, c).faces;
    faces.erase(std::remove(faces.begin(), faces.end(), g), faces.end());
    return true;
}

// Removes the merged-away faces (a face whose parent was merged away gets the face it was merged
// into as parent) and renumbers CutReport::cut_faces the same way.
void compact_merged(Editor& ed, const std::vector<Index>& merged_into) {
    mesh::Mesh& m = ed.m;
    auto survivor = [&](Index f) {
        while (f != kNone && std::size_t(f) < merged_into.size()
            && merged_into[std::size_t(f)] != kNone)
            f = merged_into[std::size_t(f)];
        return f;
    };
    std::vector<char> dead(m.faces.size(), 0);
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        dead[f] = merged_into[f] != kNone;
    for (mesh::Face& face : m.faces)
        face.parent = survivor(face.parent);
    const std::vector<Index> face_map = compact_faces(m, dead);
    CutReport& r = *ed.report;
    // the map of the faces from before the call (a second compaction in one call composes)
    const bool first = !r.faces_renumbered;
    r.faces_renumbered = true;
    if (first) {
        r.face_map.assign(face_map.begin(),
            face_map.begin()
                + std::min<std::ptrdiff_t>(r.faces_before, std::ptrdiff_t(face_map.size())));
    } else {
        for (Index& f : r.face_map)
            if (f != kNone)
                f = std::size_t(f) < face_map.size() ? face_map[std::size_t(f)] : kNone;
    }
    std::vector<Index> cut_faces;
    for (Index f : r.cut_faces)
        if (const Index g = survivor(f);
            g != kNone && std::size_t(g) < face_map.size() && face_map[std::size_t(g)] != kNone)
            cut_faces.push_back(face_map[std::size_t(g)]);
    std::sort(cut_faces.begin(), cut_faces.end());
    cut_faces.erase(std::unique(cut_faces.begin(), cut_faces.end()), cut_faces.end());
    r.cut_faces = std::move(cut_faces);
}
} // namespace

Index merge_cut_faces(Editor& ed, const std::vector<Index>& cells) {
    mesh::Mesh& m = ed.m;
    std::vector<Index> merged_into(m.faces.size(), kNone);
    Index merged = 0;
    for (Index c : cells) {
        bool changed = false;
        // Repeat until no pair merges: an order-dependent non-convex intermediate union is
        // skipped and the pieces are joined through another pairing.
        for (bool again = true; again;) {
            again = false;
            const std::vector<Index> faces = at(m.cells, c).faces;
            for (std::size_t i = 0; i < faces.size() && !again; ++i) {
                if (!is_cut_boundary(at(m.faces, faces[i])))
                    continue;
                for (std::size_t j = i + 1; j < faces.size() && !again; ++j) {
                    if (!is_cut_boundary(at(m.faces, faces[j])))
                        continue;
                    if (try_merge(ed, c, faces[i], faces[j])) {
                        merged_into[std::size_t(faces[j])] = faces[i];
                        ++merged;
                        changed = again = true;
                    }
                }
            }
        }
        if (changed)
            ed.refresh_cell_nodes(c);
    }
    if (merged > 0)
        compact_merged(ed, merged_into);
    return merged;
}

} // namespace polycut::cut::detail
