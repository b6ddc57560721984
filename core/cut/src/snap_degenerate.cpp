// Degeneracy removal (002 sec. 3.2.3, Fig. 3.8-3.9). A tet whose aspect ratio (min height / max
// edge) is below degenerate_aspect is classified by its large dihedral angles: needle (none):
// collapse the shortest edge; spindle (one): split the opposite edge where it passes the large-
// angle edge, collapse the new short edge; sliver (two): split both large-angle edges where they
// pass each other, collapse the short edge between the new nodes; cap (three): split the face
// opposite the node shared by the large angles at that node's projection, collapse. Passes repeat
// while the list of degeneracies shrinks; what is left is counted, never inverted (every collapse
// is checked: positive tets, each interior face shared by exactly two tets, a manifold boundary
// around the merged node, and a rest volume budget).
//
// The editing works on the Model of snap_model.hpp (tets with one label per local face); the face
// table is rebuilt from it afterwards and cells and nodes are compacted (snap_faces.cpp). This path
// is taken only when a degenerate tet exists.
#include "snap_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace polycut::cut::snap {
namespace {
int large_angles(const Model& md, const Tet& t, std::array<bool, 6>& large) {
    const auto ang = tet_dihedral_angles(md.s.X(t[0]), md.s.X(t[1]), md.s.X(t[2]), md.s.X(t[3]));
    int n = 0;
    for (std::size_t e = 0; e < 6; ++e) {
        large[e] = ang[e] > md.s.opt.large_dihedral;
        n += large[e] ? 1 : 0;
    }
    return n;
}

// Closest points of segments p0-p1 and q0-q1: parameters (s, t) in [0, 1].
std::pair<double, double> closest(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
    const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    const double c = d1.dot(r), b = d1.dot(d2), den = a * e - b * b;
    double sp = den > 1e-300 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.5;
    double tq = e > 0 ? std::clamp((b * sp + f) / e, 0.0, 1.0) : 0.0;
    sp = a > 0 ? std::clamp((b * tq - c) / a, 0.0, 1.0) : 0.0;
    return { sp, tq };
}

// Merges u and v, keeping a boundary node's position; tries both directions.
bool merge(Model& md, Index u, Index v, bool u_boundary, bool v_boundary) {
    if (!v_boundary && md.collapse(u, v, md.s.X(u)))
        return true;
    if (!u_boundary && md.collapse(v, u, md.s.X(v)))
        return true;
    return u_boundary && v_boundary && md.collapse(u, v, md.s.X(u));
}

bool on_boundary(const Model& md, Index n) {
    for (Index c : at(md.s.node_cells, n)) {
        const auto& t = at(md.s.m.cells, c).nodes;
        for (std::size_t k = 0; k < 4; ++k)
            if (t[k] != n && at(md.labels, c)[k] != kInterior)
                return true;
    }
    return false;
}

// One attempt to remove degenerate tet c (002 sec. 3.2.3). Splits are undone if the
// collapse fails, by restoring the snapshot.
bool remove_one(Model& md, Index c) {
    State& s = md.s;
    const Tet t = md.tet(c);
    std::array<bool, 6> large {};
    const int nl = large_angles(md, t, large);
    auto bnd = [&](Index n) { return on_boundary(md, n); };
    if (nl == 0) {
        std::size_t best = 0;
        double len = 1e300;
        for (std::size_t e = 0; e < 6; ++e) {
            const double l
                = (s.X(t[std::size_t(kTetEdges[e][0])]) - s.X(t[std::size_t(kTetEdges[e][1])]))
                      .norm();
            if (l < len) {
                len = l;
                best = e;
            }
        }
        const Index a = t[std::size_t(kTetEdges[best][0])], b = t[std::size_t(kTetEdges[best][1])];
        if (!merge(md, a, b, bnd(a), bnd(b)))
            return false;
        ++s.stats.needles_removed;
        return true;
    }
    // The splits are recorded to be taken back if the collapse after them is refused.
    Model::Journal journal;
    md.begin_journal(journal);
    const auto splits0 = std::make_tuple(s.stats.edges_split, s.stats.faces_split);
    auto undo = [&]() {
        md.undo_journal(journal);
        std::tie(s.stats.edges_split, s.stats.faces_split) = splits0;
    };
    // Every return below stops the recording (or takes the edits back).
    struct Stop {
        Model& md;
        ~Stop() { md.journal = nullptr; }
    } stop { md };
    Index m1 = kNone, other = kNone;
    if (nl == 1 || nl == 2) {
        // The large-angle edge(s); split the opposite edge where it passes the large one
        // (spindle) or both large edges where they pass each other (sliver).
        std::size_t e = 0;
        while (!large[e])
            ++e;
        const std::size_t o = 5 - e; // opposite edge in kTetEdges order
        const Index a = t[std::size_t(kTetEdges[e][0])], b = t[std::size_t(kTetEdges[e][1])];
        const Index p = t[std::size_t(kTetEdges[o][0])], q = t[std::size_t(kTetEdges[o][1])];
        const auto [se, so] = closest(s.X(a), s.X(b), s.X(p), s.X(q));
        if (!(so > 1e-3 && so < 1 - 1e-3))
            return false;
        const Vec3 Xo = s.X(p) + so * (s.X(q) - s.X(p));
        m1 = md.split({ p, q }, Xo, mix(s, p, q, so));
        ++s.stats.edges_split;
        if (nl == 2 && se > 1e-3 && se < 1 - 1e-3) {
            const Vec3 Xe = s.X(a) + se * (s.X(b) - s.X(a));
            other = md.split({ a, b }, Xe, mix(s, a, b, se));
            ++s.stats.edges_split;
        } else {
            other = (s.X(a) - Xo).norm() < (s.X(b) - Xo).norm() ? a : b;
        }
    } else {
        // Cap: the node on three large angles is over the opposite face.
        std::array<int, 4> deg {};
        for (std::size_t e = 0; e < 6; ++e)
            if (large[e]) {
                ++deg[std::size_t(kTetEdges[e][0])];
                ++deg[std::size_t(kTetEdges[e][1])];
            }
        const std::size_t d = std::size_t(std::max_element(deg.begin(), deg.end()) - deg.begin());
        std::vector<Index> f;
        for (std::size_t i = 0; i < 4; ++i)
            if (i != d)
                f.push_back(t[i]);
        const Vec3 n = (s.X(f[1]) - s.X(f[0])).cross(s.X(f[2]) - s.X(f[0])).normalized();
        const Vec3 P = s.X(t[d]) - n.dot(s.X(t[d]) - s.X(f[0])) * n;
        // Barycentric weights of P in the face.
        const double A = (s.X(f[1]) - s.X(f[0])).cross(s.X(f[2]) - s.X(f[0])).dot(n);
        std::array<double, 3> bw {};
        for (std::size_t i = 0; i < 3; ++i)
            bw[i] = (s.X(f[(i + 1) % 3]) - P).cross(s.X(f[(i + 2) % 3]) - P).dot(n) / A;
        if (*std::min_element(bw.begin(), bw.end()) < 1e-3)
            return false;
        std::map<Index, double> sum;
        for (std::size_t i = 0; i < 3; ++i)
            for (const auto& [k, w] : s.weights_of(f[i]))
                sum[k] += bw[i] * w;
        m1 = md.split(f, P, Weights(sum.begin(), sum.end()));
        ++s.stats.faces_split;
        other = t[d];
    }
    if (merge(md, other, m1, bnd(other), bnd(m1))) {
        (nl == 1          ? s.stats.spindles_removed
                : nl == 2 ? s.stats.slivers_removed
                          : s.stats.caps_removed)++;
        return true;
    }
    undo();
    return false;
}
} // namespace

void remove_degeneracies(State& s, bool all_cells) {
    Model md { s, {} };
    // The live tets to look at, in id order: every tet, or those the call changed (a pass over
    // the mesh per sweep triangle cost ~0.1 ms on the 5k organ).
    const auto candidates = [&]() {
        std::vector<Index> out;
        if (all_cells) {
            for (Index c = 0; c < s.m.num_cells(); ++c)
                if (md.alive(c))
                    out.push_back(c);
        } else {
            for (Index c : s.changed_cells())
                if (md.alive(c))
                    out.push_back(c);
        }
        return out;
    };
    std::vector<Index> list;
    for (Index c : candidates())
        if (md.degenerate(md.tet(c)))
            list.push_back(c);
    if (list.empty())
        return;
    s.stats.degenerate_found += Index(list.size());
    md.load_labels();
    for (Index c : list) {
        std::array<bool, 6> large {};
        const int nl = large_angles(md, md.tet(c), large);
        (nl == 0          ? s.stats.needles
                : nl == 1 ? s.stats.spindles
                : nl == 2 ? s.stats.slivers
                          : s.stats.caps)++;
    }
    // Passes while the list shortens (002 sec. 3.2.3).
    for (int pass = 0; pass < s.opt.max_passes; ++pass) {
        for (Index c : list)
            if (md.alive(c) && md.degenerate(md.tet(c)))
                remove_one(md, c);
        std::vector<Index> next;
        for (Index c : candidates())
            if (md.degenerate(md.tet(c)))
                next.push_back(c);
        const bool shorter = next.size() < list.size();
        list = std::move(next);
        if (!shorter || list.empty())
            break;
    }
    // What is left is incollapsible: cut it free and delete it.
    std::vector<Index> freed_nodes;
    if (s.opt.cut_free)
        for (Index c : list) {
            const Tet t = md.tet(c);
            if (md.cut_free(c)) {
                ++s.stats.cut_free;
                freed_nodes.insert(freed_nodes.end(), t.begin(), t.end());
            }
        }
    s.stats.degenerate_left = 0;
    for (Index c : candidates())
        if (md.degenerate(md.tet(c)))
            ++s.stats.degenerate_left;
    const auto nmap = rebuild_faces(md);
    // Around a deleted tet a node may now join tets that touch only there: duplicate it.
    std::sort(freed_nodes.begin(), freed_nodes.end());
    freed_nodes.erase(std::unique(freed_nodes.begin(), freed_nodes.end()), freed_nodes.end());
    for (Index n : freed_nodes)
        if (at(nmap, n) != kNone)
            split_node(s, at(nmap, n));
}

} // namespace polycut::cut::snap