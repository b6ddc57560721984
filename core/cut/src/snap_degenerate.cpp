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
// The editing works on tets (cell node lists, VTK order) with one label per local face
// (interior, skin, cut); the face table is rebuilt from them afterwards and cells and nodes are
// compacted. This path is taken only when a degenerate tet exists.
#include "snap_state.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace polycut::cut::snap {
namespace {
constexpr std::uint8_t kInterior = 0;

using Tet = std::array<Index, 4>;
using Labels = std::array<std::uint8_t, 4>; // per local face, opposite local node k

struct Model {
    State& s;
    std::vector<Labels> labels;

    Tet tet(Index c) const {
        const auto& n = at(s.m.cells, c).nodes;
        return { n[0], n[1], n[2], n[3] };
    }
    bool alive(Index c) const { return at(s.m.cells, c).nodes.size() == 4; }

    static std::array<Index, 3> key(const Tet& t, int k) {
        std::array<Index, 3> f {};
        int j = 0;
        for (int i = 0; i < 4; ++i)
            if (i != k)
                f[std::size_t(j++)] = t[std::size_t(i)];
        std::sort(f.begin(), f.end());
        return f;
    }

    double volume(const Tet& t) const {
        const Vec3& a = s.X(t[0]);
        return (s.X(t[1]) - a).dot((s.X(t[2]) - a).cross(s.X(t[3]) - a)) / 6.0;
    }
    double aspect(const Tet& t) const {
        return tet_aspect_ratio(s.X(t[0]), s.X(t[1]), s.X(t[2]), s.X(t[3]));
    }

    // 002 sec. 3.2.3: flat by aspect ratio, or with a dihedral angle close to pi (a flat tet
    // can keep an aspect ratio up to about sin(pi - large_dihedral) ~ 0.03).
    bool degenerate(const Tet& t) const {
        if (aspect(t) < s.opt.degenerate_aspect)
            return true;
        const auto ang = tet_dihedral_angles(s.X(t[0]), s.X(t[1]), s.X(t[2]), s.X(t[3]));
        return *std::max_element(ang.begin(), ang.end()) > s.opt.large_dihedral;
    }

    // Live tet other than c with the face key k, and its local face index (kNone if none).
    std::pair<Index, int> across(Index c, const std::array<Index, 3>& k) const {
        for (Index d : at(s.node_cells, k[0])) {
            if (d == c || !alive(d))
                continue;
            const Tet t = tet(d);
            for (int j = 0; j < 4; ++j)
                if (key(t, j) == k)
                    return { d, j };
        }
        return { kNone, -1 };
    }

    // Cuts tet c free and deletes it (002 sec. 3.2.3, last resort): its interior faces become
    // Cut faces of the tets across them. Refused (nothing changed) if an edge of c would be left
    // with its ring of tets in two fans (a non-manifold edge no node duplication repairs) or if
    // the rest volume budget does not cover the tet's volume.
    bool cut_free(Index c) {
        const Tet t = tet(c);
        std::vector<std::pair<Index, int>> nb;
        for (int k = 0; k < 4; ++k)
            if (at(labels, c)[std::size_t(k)] == kInterior) {
                const auto a = across(c, key(t, k));
                if (a.first != kNone)
                    nb.push_back(a);
            }
        double total = 0;
        for (Index d = 0; d < s.m.num_cells(); ++d)
            if (alive(d) && d != c)
                total += volume(tet(d));
        if (std::abs(total - s.volume0) > s.opt.max_volume_change * s.volume0)
            return false;
        for (const auto& [i, j] : kTetEdges) {
            const Index a = t[std::size_t(i)], b = t[std::size_t(j)];
            // Fans of the ring around (a, b) once c is gone: tets joined through interior faces
            // containing a and b that are not faces of c.
            std::vector<Index> ring;
            for (Index d : at(s.node_cells, a))
                if (d != c && alive(d)) {
                    const Tet u = tet(d);
                    if (std::find(u.begin(), u.end(), b) != u.end())
                        ring.push_back(d);
                }
            std::map<std::array<Index, 3>, std::vector<std::size_t>> shared;
            for (std::size_t r = 0; r < ring.size(); ++r) {
                const Tet u = tet(ring[r]);
                for (int k = 0; k < 4; ++k) {
                    const Index opp = u[std::size_t(k)];
                    if (opp == a || opp == b || at(labels, ring[r])[std::size_t(k)] != kInterior)
                        continue;
                    shared[key(u, k)].push_back(r);
                }
            }
            std::vector<std::size_t> root(ring.size());
            std::iota(root.begin(), root.end(), std::size_t(0));
            auto find = [&](std::size_t x) {
                while (root[x] != x)
                    x = root[x] = root[root[x]];
                return x;
            };
            for (const auto& [k, users] : shared)
                if (users.size() == 2 && k != key(t, 0) && k != key(t, 1) && k != key(t, 2)
                    && k != key(t, 3))
                    root[find(users[0])] = find(users[1]);
            std::size_t fans = 0;
            for (std::size_t r = 0; r < ring.size(); ++r)
                fans += find(r) == r ? 1 : 0;
            if (fans > 1)
                return false;
        }
        for (const auto& [d, j] : nb) {
            at(labels, d)[std::size_t(j)] = std::uint8_t(mesh::FaceTag::Cut);
            s.touch(d);
        }
        kill(c);
        return true;
    }

    void set_cell(Index c, const Tet& t) {
        auto& nodes = at(s.m.cells, c).nodes;
        for (Index n : nodes)
            std::erase(at(s.node_cells, n), c);
        nodes.assign(t.begin(), t.end());
        for (Index n : nodes)
            at(s.node_cells, n).push_back(c);
        s.touch(c);
    }
    void kill(Index c) {
        for (Index n : at(s.m.cells, c).nodes)
            std::erase(at(s.node_cells, n), c);
        at(s.m.cells, c).nodes.clear();
        at(s.changed, c) = 0;
    }
    Index add_cell(const Tet& t, const Labels& l, Index parent) {
        const Index c = s.m.num_cells();
        mesh::Cell cell;
        cell.shape = mesh::CellShape::Tet;
        s.m.cells.push_back(std::move(cell));
        labels.push_back(l);
        s.marks.push_back({ -1, -1, -1, -1, -1, -1 });
        s.selected.push_back(1);
        s.box.emplace_back();
        s.box_ok.push_back(0);
        s.changed.push_back(0);
        s.cell_old.push_back(kNone);
        s.cell_parent.push_back(
            at(s.cell_old, parent) != kNone ? at(s.cell_old, parent) : at(s.cell_parent, parent));
        set_cell(c, t);
        return c;
    }

    // Splits simplex `sigma` (an edge or a face, node ids) at X: every tet containing it is
    // replaced by one child per node of sigma with that node replaced by the new node.
    Index split(const std::vector<Index>& sigma, const Vec3& Xm, const Weights& w) {
        const Index m = s.add_node(Xm, w);
        std::vector<Index> around;
        for (Index c : at(s.node_cells, sigma[0])) {
            const Tet t = tet(c);
            bool all = true;
            for (Index x : sigma)
                all = all && std::find(t.begin(), t.end(), x) != t.end();
            if (all)
                around.push_back(c);
        }
        for (Index c : around) {
            const Tet t = tet(c);
            const Labels l = at(labels, c);
            auto in_sigma
                = [&](Index x) { return std::find(sigma.begin(), sigma.end(), x) != sigma.end(); };
            bool first = true;
            for (std::size_t si = 0; si < 4; ++si) {
                if (!in_sigma(t[si]))
                    continue;
                Tet child = t;
                child[si] = m;
                Labels cl = l;
                for (std::size_t k = 0; k < 4; ++k)
                    if (k != si && in_sigma(t[k]))
                        cl[k] = kInterior; // face between two children
                if (first) {
                    at(labels, c) = cl;
                    set_cell(c, child);
                    first = false;
                } else {
                    add_cell(child, cl, c);
                }
            }
        }
        return m;
    }

    // Merges node v into node u placed at Xu. Returns false (nothing changed) if the result
    // would be invalid.
    bool collapse(Index u, Index v, const Vec3& Xu) {
        std::vector<Index> star = at(s.node_cells, u);
        for (Index c : at(s.node_cells, v))
            if (std::find(star.begin(), star.end(), c) == star.end())
                star.push_back(c);
        const Vec3 Xu0 = s.X(u);
        double v_old = 0;
        for (Index c : star)
            v_old += volume(tet(c));
        // New tets and labels of the star.
        std::map<Index, Tet> next;
        std::map<Index, Labels> lab;
        std::vector<Index> removed;
        for (Index c : star) {
            Tet t = tet(c);
            const bool hu = std::find(t.begin(), t.end(), u) != t.end();
            const bool hv = std::find(t.begin(), t.end(), v) != t.end();
            if (hu && hv) {
                removed.push_back(c);
                continue;
            }
            std::replace(t.begin(), t.end(), v, u);
            next[c] = t;
            lab[c] = at(labels, c);
        }
        // Glue the two outer neighbours of each removed tet (002 Fig. 3.9).
        std::map<std::array<Index, 3>, std::vector<std::pair<Index, int>>> faces;
        for (const auto& [c, t] : next)
            for (int k = 0; k < 4; ++k)
                faces[key(t, k)].emplace_back(c, k);
        for (Index r : removed) {
            const Tet t = tet(r);
            const int ku = int(std::find(t.begin(), t.end(), u) - t.begin());
            const int kv = int(std::find(t.begin(), t.end(), v) - t.begin());
            // Face opposite u (contains v) and opposite v (contains u) both map to this key.
            Tet tu = t;
            std::replace(tu.begin(), tu.end(), v, u);
            const auto k = key(tu, ku);
            const std::uint8_t lu = at(labels, r)[std::size_t(ku)];
            const std::uint8_t lv = at(labels, r)[std::size_t(kv)];
            auto it = faces.find(k);
            if (it == faces.end())
                continue;
            for (auto& [c, kk] : it->second) {
                auto& l = lab[c][std::size_t(kk)];
                if (l != kInterior)
                    continue; // a boundary face of a surviving tet stays
                // The neighbour across the face opposite u (it had v) now borders what was
                // across the face opposite v, and the other way round.
                const Tet orig = tet(c);
                const bool had_v = std::find(orig.begin(), orig.end(), v) != orig.end();
                l = had_v ? lv : lu;
            }
        }
        at(s.m.rest, u) = Xu;
        bool ok = true;
        double v_new = 0;
        std::map<std::array<Index, 3>, std::vector<std::pair<Index, int>>> after;
        std::map<std::pair<Index, Index>, int> bedges;
        for (const auto& [c, t] : next) {
            const double vol = volume(t);
            v_new += vol;
            if (std::find(t.begin(), t.end(), u) == t.end())
                continue;
            ok = ok && vol > 0 && aspect(t) >= std::max(s.opt.snap_min_aspect, 1e-12);
            for (int k = 0; k < 4; ++k) {
                if (t[std::size_t(k)] == u)
                    continue;
                after[key(t, k)].emplace_back(c, k);
            }
        }
        for (const auto& [k, users] : after) {
            int interior = 0;
            for (const auto& [c, kk] : users) {
                if (lab[c][std::size_t(kk)] == kInterior) {
                    ++interior;
                    continue;
                }
                // Outward loop of a boundary face: count its directed edges at u.
                const Tet& t = next[c];
                const auto& lf = mesh::kTetFaces[std::size_t(kFaceOpposite[std::size_t(kk)])];
                for (std::size_t i = 0; i < 3; ++i) {
                    const Index a = t[std::size_t(lf[i])], b = t[std::size_t(lf[(i + 1) % 3])];
                    if (a == u || b == u)
                        ++bedges[{ a, b }];
                }
            }
            ok = ok && (interior == 0 || interior == 2) && users.size() <= 2
                && !(interior == 2 && users.size() != 2);
        }
        for (const auto& [e, n] : bedges) {
            const auto it = bedges.find({ e.second, e.first });
            ok = ok && n == 1 && it != bedges.end() && it->second == 1;
        }
        // Interior collapses keep the volume; boundary ones spend the budget.
        const double dv = std::abs(v_new - v_old);
        double total = 0;
        if (ok && dv > 1e-12 * std::abs(v_old)) {
            for (Index c = 0; c < s.m.num_cells(); ++c)
                if (alive(c) && !next.count(c)
                    && std::find(removed.begin(), removed.end(), c) == removed.end())
                    total += volume(tet(c));
            total += v_new;
            ok = std::abs(total - s.volume0) <= s.opt.max_volume_change * s.volume0;
        }
        if (!ok) {
            at(s.m.rest, u) = Xu0;
            return false;
        }
        if (at(s.node_old, u) != kNone)
            s.moved_from.try_emplace(u, Xu0);
        for (Index r : removed)
            kill(r);
        for (const auto& [c, t] : next) {
            at(labels, c) = lab[c];
            at(s.marks, c) = { -1, -1, -1, -1, -1, -1 };
            set_cell(c, t);
        }
        ++s.stats.edges_collapsed;
        return true;
    }
};

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

Weights mix(const State& s, Index a, Index b, double t) {
    std::map<Index, double> sum;
    for (const auto& [n, w] : s.weights_of(a))
        sum[n] += (1 - t) * w;
    for (const auto& [n, w] : s.weights_of(b))
        sum[n] += t * w;
    return { sum.begin(), sum.end() };
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
    // Snapshot for undoing splits.
    const auto cells0 = s.m.cells;
    const auto labels0 = md.labels;
    const auto node_cells0 = s.node_cells;
    const auto marks0 = s.marks;
    const auto rest_n = s.m.rest.size();
    const auto changed0 = s.changed;
    const auto splits0 = std::make_tuple(s.stats.edges_split, s.stats.faces_split);
    auto undo = [&]() {
        s.m.cells = cells0;
        md.labels = labels0;
        s.node_cells = node_cells0;
        s.marks = marks0;
        s.changed = changed0;
        for (Index n = Index(rest_n); n < s.m.num_nodes(); ++n)
            s.new_weights.erase(n);
        s.m.rest.resize(rest_n);
        s.node_old.resize(rest_n);
        const std::size_t nc = s.m.cells.size();
        s.selected.resize(nc);
        s.box.resize(nc);
        s.box_ok.assign(nc, 0);
        s.cell_old.resize(nc);
        s.cell_parent.resize(nc);
        std::tie(s.stats.edges_split, s.stats.faces_split) = splits0;
    };
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

// Rebuilds the face table from the tets and labels, compacts cells and nodes; returns the node
// map (old -> new id, kNone if unused).
std::vector<Index> rebuild_faces(Model& md) {
    State& s = md.s;
    mesh::Mesh& m = s.m;
    // Pending faces survive by their node sets.
    std::vector<std::array<Index, 3>> pend;
    for (Index f : s.pending) {
        const auto& n = at(m.faces, f).nodes;
        std::array<Index, 3> k { n[0], n[1], n[2] };
        std::sort(k.begin(), k.end());
        pend.push_back(k);
    }
    // Compact cells.
    std::vector<Index> cmap(m.cells.size(), kNone);
    Index nc = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        if (!md.alive(c)) {
            if (at(s.cell_old, c) != kNone)
                s.removed_cells_old.push_back(at(s.cell_old, c));
            continue;
        }
        at(cmap, c) = nc;
        const std::size_t to = std::size_t(nc++), from = std::size_t(c);
        if (to == from)
            continue;
        m.cells[to] = std::move(m.cells[from]);
        md.labels[to] = md.labels[from];
        s.marks[to] = s.marks[from];
        s.selected[to] = s.selected[from];
        s.changed[to] = s.changed[from];
        s.cell_old[to] = s.cell_old[from];
        s.cell_parent[to] = s.cell_parent[from];
    }
    for (auto* v : { &s.cell_old, &s.cell_parent })
        v->resize(std::size_t(nc));
    m.cells.resize(std::size_t(nc));
    md.labels.resize(std::size_t(nc));
    s.marks.resize(std::size_t(nc));
    s.selected.resize(std::size_t(nc));
    s.changed.resize(std::size_t(nc));
    s.box.assign(std::size_t(nc), {});
    s.box_ok.assign(std::size_t(nc), 0);
    // Compact nodes.
    std::vector<char> used(m.rest.size(), 0);
    for (const auto& cell : m.cells)
        for (Index n : cell.nodes)
            at(used, n) = 1;
    std::vector<Index> nmap(m.rest.size(), kNone);
    Index nn = 0;
    std::unordered_map<Index, Weights> weights;
    std::unordered_map<Index, Vec3> moved;
    for (Index n = 0; n < m.num_nodes(); ++n) {
        if (!at(used, n)) {
            if (at(s.node_old, n) != kNone)
                s.removed_nodes_old.push_back(at(s.node_old, n));
            continue;
        }
        at(nmap, n) = nn;
        m.rest[std::size_t(nn)] = m.rest[std::size_t(n)];
        s.node_old[std::size_t(nn)] = s.node_old[std::size_t(n)];
        if (auto it = s.new_weights.find(n); it != s.new_weights.end())
            weights.emplace(nn, it->second);
        if (auto it = s.moved_from.find(n); it != s.moved_from.end())
            moved.emplace(nn, it->second);
        ++nn;
    }
    m.rest.resize(std::size_t(nn));
    s.node_old.resize(std::size_t(nn));
    s.new_weights = std::move(weights);
    s.moved_from = std::move(moved);
    std::vector<std::pair<Index, Index>> dup;
    for (const auto& [a, b] : s.duplicated)
        if (at(nmap, a) != kNone && at(nmap, b) != kNone)
            dup.emplace_back(at(nmap, a), at(nmap, b));
    s.duplicated = std::move(dup);
    for (auto& cell : m.cells)
        for (Index& n : cell.nodes)
            n = at(nmap, n);
    for (auto& k : pend)
        for (Index& n : k)
            n = at(nmap, n);
    // Faces.
    m.faces.clear();
    auto hash = [](std::array<Index, 3> k) {
        return (std::uint64_t(std::uint32_t(k[0])) * 0x9E3779B97F4A7C15ull)
            ^ (std::uint64_t(std::uint32_t(k[1])) << 21)
            ^ (std::uint64_t(std::uint32_t(k[2])) << 42) ^ std::uint64_t(std::uint32_t(k[2]) >> 22);
    };
    std::multimap<std::uint64_t, Index> byhash;
    for (Index c = 0; c < m.num_cells(); ++c) {
        auto& cell = at(m.cells, c);
        cell.faces.clear();
        for (std::size_t k = 0; k < 4; ++k) {
            const auto& lf = mesh::kTetFaces[std::size_t(kFaceOpposite[k])];
            std::vector<Index> loop { cell.nodes[std::size_t(lf[0])],
                cell.nodes[std::size_t(lf[1])], cell.nodes[std::size_t(lf[2])] };
            std::array<Index, 3> key { loop[0], loop[1], loop[2] };
            std::sort(key.begin(), key.end());
            const std::uint8_t l = at(md.labels, c)[k];
            if (l == kInterior) {
                const std::uint64_t h = hash(key);
                Index match = kNone;
                for (auto [it, end] = byhash.equal_range(h); it != end; ++it) {
                    auto k2 = at(m.faces, it->second).nodes;
                    std::sort(k2.begin(), k2.end());
                    if (std::equal(k2.begin(), k2.end(), key.begin())) {
                        match = it->second;
                        byhash.erase(it);
                        break;
                    }
                }
                if (match != kNone) {
                    at(m.faces, match).neighbour = c;
                    at(m.faces, match).tag = mesh::FaceTag::Interior;
                    cell.faces.push_back(match);
                    continue;
                }
                mesh::Face f;
                f.nodes = std::move(loop);
                f.owner = c;
                f.tag = mesh::FaceTag::Cut; // becomes Interior when matched
                byhash.emplace(h, m.num_faces());
                cell.faces.push_back(m.num_faces());
                m.faces.push_back(std::move(f));
            } else {
                mesh::Face f;
                f.nodes = std::move(loop);
                f.owner = c;
                f.tag = mesh::FaceTag(l);
                cell.faces.push_back(m.num_faces());
                m.faces.push_back(std::move(f));
            }
        }
    }
    s.node_cells = m.node_cells();
    s.pending.clear();
    for (const auto& k : pend) {
        if (std::find(k.begin(), k.end(), kNone) != k.end())
            continue;
        for (Index c : at(s.node_cells, k[0]))
            for (Index f : at(m.cells, c).faces) {
                auto k2 = at(m.faces, f).nodes;
                std::sort(k2.begin(), k2.end());
                if (std::equal(k2.begin(), k2.end(), k.begin()) && !at(m.faces, f).boundary()
                    && std::find(s.pending.begin(), s.pending.end(), f) == s.pending.end())
                    s.pending.push_back(f);
            }
    }
    s.compacted = true;
    return nmap;
}
} // namespace

void remove_degeneracies(State& s, bool all_cells) {
    Model md { s, {} };
    auto candidate = [&](Index c) { return md.alive(c) && (all_cells || at(s.changed, c)); };
    std::vector<Index> list;
    for (Index c = 0; c < s.m.num_cells(); ++c)
        if (candidate(c) && md.degenerate(md.tet(c)))
            list.push_back(c);
    if (list.empty())
        return;
    s.stats.degenerate_found += Index(list.size());
    md.labels.resize(s.m.cells.size());
    for (Index c = 0; c < s.m.num_cells(); ++c) {
        const auto& nodes = at(s.m.cells, c).nodes;
        for (Index f : at(s.m.cells, c).faces) {
            const auto& face = at(s.m.faces, f);
            for (std::size_t k = 0; k < 4; ++k)
                if (std::find(face.nodes.begin(), face.nodes.end(), nodes[k]) == face.nodes.end())
                    at(md.labels, c)[k] = face.boundary() ? std::uint8_t(face.tag) : kInterior;
        }
    }
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
        for (Index c = 0; c < s.m.num_cells(); ++c)
            if (candidate(c) && md.degenerate(md.tet(c)))
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
    for (Index c = 0; c < s.m.num_cells(); ++c)
        if (candidate(c) && md.degenerate(md.tet(c)))
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
