// Face selection by closest nodes (002 sec. 3.2.1, Fig. 3.1-3.4): every edge the sweep triangle
// crosses marks its node closest to the crossing (the lower id on a tie); marks stay with the tet
// between triangles (only the first crossing of an edge counts), and a tet whose marks name three
// nodes selects the face of those nodes. Crossings are computed once per edge and triangle, so
// all tets around an edge see the same mark and the selected surface is connected.
#include "snap_state.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

namespace polycut::cut::snap {
namespace {
// Whether Q (in the plane of P) lies in P's triangle, up to eps [m] outside its edges.
bool in_sweep_triangle(const SweepPlane& P, const Vec3& Q, double eps) {
    for (int k = 0; k < 3; ++k) {
        const Vec3& p = P.tri[std::size_t(k)];
        const Vec3& q = P.tri[std::size_t((k + 1) % 3)];
        if ((q - p).cross(Q - p).dot(P.normal) < -eps * (q - p).norm())
            return false;
    }
    return true;
}

// Node marked on edge (a, b), or kNone if the triangle does not cross it. Edges lying in the
// plane are ignored: their nodes are marked by the edges that reach the plane at them.
Index crossing(const State& s, const SweepPlane& P, double eps, Index a, Index b) {
    const Vec3& Xa = s.X(a);
    const Vec3& Xb = s.X(b);
    double da = P.distance(Xa), db = P.distance(Xb);
    if (std::abs(da) <= eps)
        da = 0;
    if (std::abs(db) <= eps)
        db = 0;
    if (da == 0 && db == 0)
        return kNone;
    if ((da > 0 && db > 0) || (da < 0 && db < 0))
        return kNone;
    const double t = da == 0 ? 0.0 : (db == 0 ? 1.0 : da / (da - db));
    if (!in_sweep_triangle(P, Xa + t * (Xb - Xa), eps))
        return kNone;
    if (t < 0.5)
        return a;
    if (t > 0.5)
        return b;
    return std::min(a, b);
}

std::uint64_t edge_key(Index a, Index b) {
    if (a > b)
        std::swap(a, b);
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

// Selects the face of tet c named by three marks (002 sec. 3.2.1).
void evaluate(State& s, const SweepPlane& P, Index c, std::vector<Index>& found) {
    const auto& mk = at(s.marks, c);
    const auto& nodes = at(s.m.cells, c).nodes;
    if (at(s.selected, c))
        return;
    std::array<bool, 4> marked {};
    int count = 0;
    for (std::int8_t k : mk)
        if (k >= 0 && !marked[std::size_t(k)]) {
            marked[std::size_t(k)] = true;
            ++count;
        }
    if (count < 3)
        return;
    // Three marks select the face opposite the unmarked node. Four (all edges crossed at
    // their middles, or two sweeps crossing the tet differently) select the face opposite
    // the node farthest from the current plane (002 picks one at random).
    int out = 0;
    if (count == 3) {
        while (marked[std::size_t(out)])
            ++out;
    } else {
        double far = -1;
        for (int k = 0; k < 4; ++k) {
            const double d = std::abs(P.distance(s.X(nodes[std::size_t(k)])));
            if (d > far) {
                far = d;
                out = k;
            }
        }
    }
    at(s.selected, c) = 1;
    const Index f = s.global_face(c, kFaceOpposite[std::size_t(out)]);
    if (f == kNone || at(s.m.faces, f).boundary())
        return;
    // Only where the blade has passed (docs/decisions/0008): a face whose centroid lies beyond
    // the swept surface would extend the cut past the blade's edges.
    // Such a tet is tried again after each later triangle of the stroke (retry_deferred).
    if (s.opt.snap_nodes) {
        Vec3 mid = Vec3::Zero();
        for (Index n : at(s.m.faces, f).nodes)
            mid += s.X(n) / 3.0;
        if (!on_swept_surface(s, P, mid - P.distance(mid) * P.normal)) {
            at(s.selected, c) = 0;
            if (std::find(s.deferred.begin(), s.deferred.end(), c) == s.deferred.end())
                s.deferred.push_back(c);
            return;
        }
    }
    if (std::find(s.pending.begin(), s.pending.end(), f) != s.pending.end())
        return;
    s.pending.push_back(f);
    found.push_back(f);
    ++s.stats.faces_selected;
}
} // namespace

std::vector<Index> select_faces(State& s, const SweepPlane& P) {
    const double eps = s.opt.plane_eps * s.L;
    geometry::Aabb tb;
    for (const Vec3& p : P.tri)
        tb.extend(p);
    tb.lo.array() -= eps;
    tb.hi.array() += eps;
    std::unordered_map<std::uint64_t, Index> cache;
    std::vector<Index> selected_now;
    s.near.clear();
    const std::vector<Index> cells = s.candidates(tb); // copied: evaluate() may query again
    for (Index c : cells) {
        if (!s.bounds(c).overlaps(tb))
            continue;
        s.near.push_back(c);
        auto& mk = at(s.marks, c);
        const auto& nodes = at(s.m.cells, c).nodes;
        bool changed = false;
        for (std::size_t e = 0; e < 6; ++e) {
            if (mk[e] >= 0)
                continue;
            const auto [i, j] = kTetEdges[e];
            const Index a = nodes[std::size_t(i)], b = nodes[std::size_t(j)];
            auto [it, fresh] = cache.try_emplace(edge_key(a, b), kNone);
            if (fresh) {
                it->second = crossing(s, P, eps, a, b);
                if (it->second != kNone)
                    ++s.stats.edges_crossed;
            }
            if (it->second == kNone)
                continue;
            mk[e] = std::int8_t(it->second == a ? i : j);
            changed = true;
        }
        if (changed)
            evaluate(s, P, c, selected_now);
    }
    return selected_now;
}

std::vector<Index> retry_deferred(State& s, const SweepPlane& P) {
    std::vector<Index> found;
    const std::vector<Index> tets = std::exchange(s.deferred, {});
    for (Index c : tets)
        if (c < s.m.num_cells())
            evaluate(s, P, c, found);
    return found;
}

std::vector<Index> mark_snapped_nodes(
    State& s, const SweepPlane& P, const std::vector<Index>& nodes) {
    // A snapped node lies on the sweep, so every edge at it now meets the sweep at the node. If
    // the node moved into the part already swept, no later triangle would find those crossings
    // and the tets around it would never complete; they are marked now.
    const double eps = s.opt.plane_eps * s.L;
    std::vector<Index> out;
    for (Index v : nodes)
        for (Index c : at(s.node_cells, v)) {
            auto& mk = at(s.marks, c);
            const auto& cn = at(s.m.cells, c).nodes;
            bool changed = false;
            for (std::size_t e = 0; e < 6; ++e) {
                const auto [i, j] = kTetEdges[e];
                if (mk[e] >= 0 || (cn[std::size_t(i)] != v && cn[std::size_t(j)] != v))
                    continue;
                const Index u = cn[std::size_t(i)] == v ? cn[std::size_t(j)] : cn[std::size_t(i)];
                if (std::abs(P.distance(s.X(u))) <= eps)
                    continue;
                mk[e] = std::int8_t(cn[std::size_t(i)] == v ? i : j);
                changed = true;
            }
            if (changed)
                evaluate(s, P, c, out);
        }
    return out;
}

void select_faces_in_plane(State& s, const SweepPlane& P) {
    // Snapping moves nodes marked by other tets or earlier triangles onto the plane too, and the
    // per-tet rule above cannot see a face whose nodes were marked from outside its tets. Such a
    // face lies in the sweep between tets on opposite sides of it; left uncut it would bridge
    // the incision, so it is selected as well (an addition to 002 sec. 3.2.1).
    const double eps = s.opt.plane_eps * s.L;
    auto apex = [&](Index c, const std::vector<Index>& face) {
        for (Index n : at(s.m.cells, c).nodes)
            if (std::find(face.begin(), face.end(), n) == face.end())
                return P.distance(s.X(n));
        return 0.0;
    };
    for (Index c : s.near)
        for (Index f : at(s.m.cells, c).faces) {
            const mesh::Face& face = at(s.m.faces, f);
            if (face.boundary() || face.owner != c)
                continue;
            Vec3 mid = Vec3::Zero();
            bool on = true;
            for (Index n : face.nodes) {
                on = on && std::abs(P.distance(s.X(n))) <= eps;
                mid += s.X(n) / 3.0;
            }
            // In any triangle of the stroke in this plane: the faces snapped in here may lie
            // where earlier, thinner strips of the sweep passed.
            if (!on || !(in_sweep_triangle(P, mid, eps) || on_swept_surface(s, P, mid)))
                continue;
            const double d1 = apex(face.owner, face.nodes), d2 = apex(face.neighbour, face.nodes);
            if (!((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)))
                continue;
            if (std::find(s.pending.begin(), s.pending.end(), f) != s.pending.end())
                continue;
            s.pending.push_back(f);
            ++s.stats.faces_selected;
        }
}

} // namespace polycut::cut::snap

// Selection against the stroke as one swept surface (docs/decisions/0008; an addition to
// 002 sec. 3.2.1-3.2.2).
// 002 sec. 3.2.1 selects a face when the edges of one tet have been crossed three times by the
// sweep. A blade sampled once per tick sweeps strips narrower than a cell, and a blade between
// two grid planes crosses most tets on one or two edges only, so that rule leaves rows of faces
// unselected (0 for a 1 cm stroke at 0.1 mm per tick on 1 cm cells). Here each face is judged
// against the surface the whole stroke has swept (State::swept, reset by end_sweep); an interior
// face is cut when
//   1. its centroid, projected onto the plane of a sweep triangle, lies in that triangle (a point
//      of the union of the stroke's triangles lies in one of them, so thin strips of many ticks
//      add up; the blade's edges round the cut to whole faces by centroid, which has no bias);
//   2. each of its nodes lies on that plane or is the closest node of an edge crossing it
//      (002 sec. 3.2.1's rule, lower id on a tie, applied to the triangle's plane);
//   3. neither of its tets has a face cut or selected already (a second one would wrap the tet
//      into a piece of its own), and once its nodes are snapped onto the plane (002 sec. 3.2.2,
//      same boundary rules and inversion guard) the two tets lie on opposite sides of the plane.
// This runs after 002's per-tet rule, which still cuts where snaps are refused (jagged pieces),
// but under rule 1 too: a tet whose marks name a face the blade has not swept yet is deferred
// and tried again after each later triangle, so no rule cuts beyond the blade's edges. Faces
// other triangles' snaps put into the plane are cut under rule 1 by select_faces_in_plane.
// Rule 2 bounds the snap: a node moves at most half the length of an edge of its own, along the
// plane's normal (or within its boundary faces). Nodes on faces an earlier cut opened stay where
// they are (moving one copy of a duplicated node would part the two lips in rest space).

namespace polycut::cut::snap {
namespace {

// Rule 2: v lies on the plane, or some edge at v crosses it and v is its closer end.
bool closest_node(const State& s, const SweepPlane& P, double eps, Index v) {
    const double dv = P.distance(s.X(v));
    if (std::abs(dv) <= eps)
        return true;
    for (Index c : at(s.node_cells, v))
        for (Index u : at(s.m.cells, c).nodes) {
            if (u == v)
                continue;
            const double du = P.distance(s.X(u));
            if (std::abs(du) <= eps || (du > 0) == (dv > 0))
                continue;
            if (std::abs(dv) < std::abs(du) || (std::abs(dv) == std::abs(du) && v < u))
                return true;
        }
    return false;
}

// Whether v lies on a face an earlier cut opened (a lip of the incision).
bool on_cut(const State& s, Index v) {
    for (Index c : at(s.node_cells, v))
        for (Index f : at(s.m.cells, c).faces) {
            const mesh::Face& face = at(s.m.faces, f);
            if (face.tag == mesh::FaceTag::Cut
                && std::find(face.nodes.begin(), face.nodes.end(), v) != face.nodes.end())
                return true;
        }
    return false;
}

// Whether tet c has a face that is cut or selected for cutting.
bool has_cut_face(const State& s, Index c) {
    for (Index f : at(s.m.cells, c).faces)
        if (at(s.m.faces, f).tag == mesh::FaceTag::Cut
            || std::find(s.pending.begin(), s.pending.end(), f) != s.pending.end())
            return true;
    return false;
}

// Signed distance of the node of tet c that is not on face f.
double apex(const State& s, const SweepPlane& P, Index c, const std::vector<Index>& face) {
    for (Index n : at(s.m.cells, c).nodes)
        if (std::find(face.begin(), face.end(), n) == face.end())
            return P.distance(s.X(n));
    return 0.0;
}

bool opposite(const State& s, const SweepPlane& P, const mesh::Face& face, double eps) {
    const double d1 = apex(s, P, face.owner, face.nodes);
    const double d2 = apex(s, P, face.neighbour, face.nodes);
    return (d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps);
}
} // namespace

bool on_swept_surface(const State& s, const SweepPlane& P, const Vec3& x) {
    const double eps = s.opt.plane_eps * s.L;
    for (const SweepPlane& R : s.swept)
        if ((x.array() >= R.box.lo.array() - eps).all()
            && (x.array() <= R.box.hi.array() + eps).all() && R.normal.dot(P.normal) >= 1 - 1e-9
            && std::abs(R.distance(x)) <= eps && in_sweep_triangle(R, x, eps))
            return true;
    return false;
}

std::vector<Index> select_swept_faces(State& s, const SweepPlane& P) {
    const double eps = s.opt.plane_eps * s.L;
    // Faces lie within an edge of the plane (rule 2), their centroids over the triangle: the
    // owner's bounds hold the centroid, so they meet the triangle's box grown by eps and, along
    // the normal only, by the largest cell extent near the triangle (the length of any edge
    // that crosses it). Growing it by that extent in every direction would take ~10x the tets.
    geometry::Aabb tb;
    for (const Vec3& p : P.tri)
        tb.extend(p);
    double reach = 0;
    for (Index c : s.near)
        reach = std::max(reach, s.bounds(c).diagonal());
    const Vec3 slab = reach * P.normal.cwiseAbs();
    tb.lo = tb.lo - slab - Vec3::Constant(eps);
    tb.hi = tb.hi + slab + Vec3::Constant(eps);
    std::unordered_map<Index, bool> closest; // rule 2, per node, cached for this triangle
    auto is_closest = [&](Index v) {
        auto [it, fresh] = closest.try_emplace(v, false);
        if (fresh)
            it->second = closest_node(s, P, eps, v)
                && (std::abs(P.distance(s.X(v))) <= eps || !on_cut(s, v));
        return it->second;
    };
    std::vector<Index> faces;
    const std::vector<Index> cells = s.candidates(tb);
    for (Index c : cells) {
        if (!s.bounds(c).overlaps(tb))
            continue;
        for (Index f : at(s.m.cells, c).faces) {
            const mesh::Face& face = at(s.m.faces, f);
            // Each interior face once, from its owner.
            if (face.boundary() || face.owner != c || face.nodes.size() != 3)
                continue;
            Vec3 mid = Vec3::Zero();
            for (Index n : face.nodes)
                mid += s.X(n) / 3.0;
            if (!in_sweep_triangle(P, mid, eps) || !opposite(s, P, face, eps))
                continue;
            if (!std::all_of(face.nodes.begin(), face.nodes.end(), is_closest))
                continue;
            if (std::find(s.pending.begin(), s.pending.end(), f) != s.pending.end())
                continue;
            // A tet keeps at most one face of the cut: a second one, across the tet from a face
            // 002's rule or an earlier cut chose, would wrap it into a piece of its own.
            if (has_cut_face(s, face.owner) || has_cut_face(s, face.neighbour))
                continue;
            faces.push_back(f);
        }
    }
    const std::vector<Index> moved = snap_face_nodes(s, P, faces);
    for (Index f : faces) {
        const mesh::Face& face = at(s.m.faces, f);
        const bool on = std::all_of(face.nodes.begin(), face.nodes.end(),
            [&](Index n) { return std::abs(P.distance(s.X(n))) <= eps; });
        if (!on || !opposite(s, P, face, eps))
            continue; // a snap was refused, or the tets around it were snapped flat
        s.pending.push_back(f);
        ++s.stats.faces_selected;
    }
    return moved;
}

} // namespace polycut::cut::snap
