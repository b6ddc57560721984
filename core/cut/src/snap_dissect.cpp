// Dissection along the selected faces (002 sec. 3.2, step 3): each face becomes two Cut boundary
// faces, one per side, and every node of those faces is duplicated once per group of its tets that
// are no longer connected through interior faces around it. Nodes at the crack front stay shared.
//
// A face set can pinch an edge: two cut faces around an edge (or one at a skin edge) split the
// ring of tets around it while neither end node separates, so four boundary faces would meet at
// the edge (a non-manifold boundary). The cell-splitting cutter fixes that with a midpoint node;
// with a constant cell count we hold such faces back instead (newest first) and retry them after
// later triangles, when the cut around them has grown and their nodes separate. This is the lag
// between sweep and incision 002 Fig. 3.4 describes, one face row wider at a narrow crack tip.
// A face still held back where the sweep has passed all around its pinched edges will not be
// freed by later triangles (the pinch comes from the shape of the selected surface, e.g. a hole
// left by a refused snap): there the pinched edges are split at their midpoints, as the
// cell-splitting cutter does, and the face is cut (the midpoint nodes separate the two sides).
#include "snap_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace polycut::cut::snap {
namespace {
bool has(const std::vector<Index>& v, Index x) {
    return std::find(v.begin(), v.end(), x) != v.end();
}

struct Dsu {
    explicit Dsu(std::size_t n)
        : p(n) {
        std::iota(p.begin(), p.end(), std::size_t(0));
    }
    std::size_t find(std::size_t a) {
        while (p[a] != a)
            a = p[a] = p[p[a]];
        return a;
    }
    void join(std::size_t a, std::size_t b) { p[find(a)] = find(b); }
    std::vector<std::size_t> p;
};

struct Pinch {
    const State& s;
    const std::unordered_set<Index>& extra; // faces to be cut on top of the boundary
    /// groups() of each node's whole star as last computed: it depends on whether the faces at
    /// the node are cut, so changed(f) forgets the stars of f's nodes. A held-back face's edges
    /// are checked again after each face dropped near it, and most checks asked for the same
    /// few stars again (the pinch checks were ~40 % of a random soup's face-snapping cut).
    mutable std::unordered_map<Index, std::vector<std::size_t>> stars;
    /// The interior faces joining two tets of a node's star (slots in its node_cells, the
    /// owner first), found once per node: a Pinch lives within one pass over a mesh that only
    /// changes which faces are cut (in `extra`), and grouping a star again after a change then
    /// reads these instead of searching each tet's faces and neighbours (~45 % of a random
    /// soup's face-snapping cut was that search).
    struct Link {
        std::uint32_t i, j;
        Index face;
    };
    mutable std::unordered_map<Index, std::vector<Link>> links;

    /// Face f was added to or taken from `extra`.
    void changed(Index f) const {
        for (Index n : at(s.m.faces, f).nodes)
            stars.erase(n);
    }
    void forget() const { stars.clear(); }
    const std::vector<std::size_t>& star(Index a) const {
        auto it = stars.find(a);
        if (it == stars.end())
            it = stars.emplace(a, star_groups(a)).first;
        return it->second;
    }

    const std::vector<Link>& star_links(Index a) const {
        auto it = links.find(a);
        if (it != links.end())
            return it->second;
        const auto& cells = at(s.node_cells, a);
        std::vector<Link> out;
        for (std::size_t i = 0; i < cells.size(); ++i)
            for (Index f : at(s.m.cells, cells[i]).faces) {
                const mesh::Face& face = at(s.m.faces, f);
                if (face.boundary() || face.owner != cells[i] || !has(face.nodes, a))
                    continue; // each interior face once, from its owner
                const auto jt = std::find(cells.begin(), cells.end(), face.neighbour);
                if (jt != cells.end())
                    out.push_back({ std::uint32_t(i), std::uint32_t(jt - cells.begin()), f });
            }
        return links.emplace(a, std::move(out)).first->second;
    }

    // groups(node_cells(a), { a }) from the star's links.
    std::vector<std::size_t> star_groups(Index a) const {
        Dsu d(at(s.node_cells, a).size());
        for (const Link& l : star_links(a))
            if (!extra.count(l.face))
                d.join(l.i, l.j);
        std::vector<std::size_t> root(d.p.size());
        for (std::size_t i = 0; i < root.size(); ++i)
            root[i] = d.find(i);
        return root;
    }

    bool cut(Index f) const { return at(s.m.faces, f).boundary() || extra.count(f) > 0; }

    // Root of each cell of `cells` when joined through uncut faces containing all `keys`.
    std::vector<std::size_t> groups(
        const std::vector<Index>& cells, std::initializer_list<Index> keys) const {
        Dsu d(cells.size());
        for (std::size_t i = 0; i < cells.size(); ++i)
            for (Index f : at(s.m.cells, cells[i]).faces) {
                const mesh::Face& face = at(s.m.faces, f);
                bool all = true;
                for (Index k : keys)
                    all = all && has(face.nodes, k);
                if (!all || cut(f)) // the node test first: it spares most hash look-ups
                    continue;
                const Index other = face.owner == cells[i] ? face.neighbour : face.owner;
                const auto it = std::find(cells.begin(), cells.end(), other);
                if (it != cells.end())
                    d.join(i, std::size_t(it - cells.begin()));
            }
        std::vector<std::size_t> root(cells.size());
        for (std::size_t i = 0; i < cells.size(); ++i)
            root[i] = d.find(i);
        return root;
    }

    bool pinched(Index a, Index b) const {
        std::vector<Index> ring;
        for (Index c : at(s.node_cells, a))
            if (has(at(s.m.cells, c).nodes, b))
                ring.push_back(c);
        if (ring.size() < 2)
            return false;
        const auto rr = groups(ring, { a, b });
        // Pinched only if the ring around the edge falls apart; most edges' rings do not, and
        // then the two node stars (the dear part: ~90 % of a random soup's face-snapping cut)
        // need not be grouped.
        if (std::all_of(rr.begin(), rr.end(), [&](std::size_t r) { return r == rr[0]; }))
            return false;
        const auto& ca = at(s.node_cells, a);
        const auto& cb = at(s.node_cells, b);
        const auto& ga = star(a);
        const auto& gb = star(b);
        auto slot = [](const std::vector<Index>& v, Index c) {
            return std::size_t(std::find(v.begin(), v.end(), c) - v.begin());
        };
        for (std::size_t i = 0; i < ring.size(); ++i)
            for (std::size_t j = i + 1; j < ring.size(); ++j)
                if (rr[i] != rr[j] && ga[slot(ca, ring[i])] == ga[slot(ca, ring[j])]
                    && gb[slot(cb, ring[i])] == gb[slot(cb, ring[j])])
                    return true;
        return false;
    }
};

// Whether the sweep has passed all around x: for a triangle of the sweep holding x, the circle of
// radius r around x in its plane (12 points) lies in the union of the sweep's triangles. The
// whole sweep counts, not only the last triangles: a blade sampled every tick sweeps strips
// narrower than a cell, and only their union covers a node's neighbourhood.
// Whether triangle P can hold a point that swept_around_now() tests around x: every point tested
// lies within 2 r of x (x within r of the outer plane, q within r of x's foot on it), and
// inside() takes points within r of a plane and eps of its triangle's edges, so only triangles
// whose box grown by 3 r + eps holds x can. (The plane's distance alone let through every
// triangle of a random soup whose plane passes near x, however far the triangle ends.)
bool may_reach(const SweepPlane& P, const Vec3& x, double r, double eps) {
    const Eigen::Array3d grow = Eigen::Array3d::Constant(3 * r + eps);
    return (x.array() >= P.box.lo.array() - grow).all()
        && (x.array() <= P.box.hi.array() + grow).all() && std::abs(P.distance(x)) <= 3 * r;
}

bool swept_around_now(const State& s, const Vec3& x, double r) {
    const double eps = s.opt.plane_eps * s.L;
    auto inside = [&](const SweepPlane& P, const Vec3& q, double tol) {
        if (std::abs(P.distance(q)) > tol)
            return false;
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = P.tri[std::size_t(k)];
            const Vec3& p2 = P.tri[std::size_t((k + 1) % 3)];
            if ((p2 - p).cross(q - p).dot(P.normal) < -eps * (p2 - p).norm())
                return false;
        }
        return true;
    };
    // Only the triangles near x (the rest of a long sweep is skipped).
    std::vector<const SweepPlane*> near;
    for (const SweepPlane& P : s.swept)
        if (may_reach(P, x, r, eps))
            near.push_back(&P);
    s.sweep_tests += s.swept.size();
    for (const SweepPlane* P : near) {
        if (!inside(*P, x, r))
            continue;
        const Vec3 u = P->normal.unitOrthogonal(), v = P->normal.cross(u);
        const Vec3 x0 = x - P->distance(x) * P->normal;
        bool all = true;
        for (int i = 0; i < 12 && all; ++i) {
            const double t = std::numbers::pi * i / 6.0;
            const Vec3 q = x0 + r * (std::cos(t) * u + std::sin(t) * v);
            all = std::any_of(near.begin(), near.end(), [&](const SweepPlane* R) {
                ++s.sweep_tests;
                return inside(*R, q, r);
            });
        }
        if (all)
            return true;
    }
    return false;
}

// swept_around_now() through State::swept_memo: open_pinches() asks it for every pinched edge of
// every held-back face after every sweep triangle (on a random soup of 2,000 triangles, ~200
// held-back faces at each of ~1,900 calls, its 12-point tests were half of the face-snapping
// cut: worst tick 198 -> 169 ms with the memo, the same cut to the bit).
bool swept_around(const State& s, Index a, Index b, double r) {
    const Vec3 x = s.X(a);
    const std::uint64_t key = (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
    State::SweptMemo& m = s.swept_memo[key];
    const std::size_t n = s.swept.size();
    if (m.x == x && m.r == r && m.upto <= n) {
        if (m.yes)
            return true; // the union of the swept triangles only grows
        // no triangle swept since can reach x's circle: still no
        const double eps = s.opt.plane_eps * s.L;
        bool near = false;
        for (std::size_t k = m.upto; k < n && !near; ++k)
            near = may_reach(s.swept[k], x, r, eps);
        s.sweep_tests += n - m.upto;
        if (!near) {
            m.upto = n;
            return false;
        }
    }
    m = { x, r, n, swept_around_now(s, x, r) };
    return m.yes;
}

// Longest edge [m] of the tets around edge (a, b).
double ring_size(const State& s, Index a, Index b) {
    double r = 0;
    for (Index c : at(s.node_cells, a)) {
        const auto& t = at(s.m.cells, c).nodes;
        if (!has(t, b))
            continue;
        for (const auto& [i, j] : kTetEdges)
            r = std::max(r, (s.X(t[std::size_t(i)]) - s.X(t[std::size_t(j)])).norm());
    }
    return r;
}

void replace_node(std::vector<Index>& v, Index from, Index to) {
    std::replace(v.begin(), v.end(), from, to);
}

} // namespace

void split_node(State& s, Index n) {
    const std::vector<Index> cells = at(s.node_cells, n);
    if (cells.size() < 2)
        return;
    const std::unordered_set<Index> none;
    const auto root = Pinch { s, none, {}, {} }.groups(cells, { n });
    std::vector<std::vector<Index>> groups;
    std::vector<std::size_t> roots;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const auto it = std::find(roots.begin(), roots.end(), root[i]);
        if (it == roots.end()) {
            roots.push_back(root[i]);
            groups.push_back({ cells[i] });
        } else {
            groups[std::size_t(it - roots.begin())].push_back(cells[i]);
        }
    }
    if (groups.size() < 2)
        return;
    for (auto& g : groups)
        std::sort(g.begin(), g.end());
    std::sort(groups.begin(), groups.end()); // the group with the smallest cell keeps n
    at(s.node_cells, n) = groups.front();
    for (std::size_t gi = 1; gi < groups.size(); ++gi) {
        const Index copy = s.add_node(s.X(n), s.weights_of(n));
        s.duplicated.emplace_back(n, copy);
        at(s.node_cells, copy) = groups[gi];
        for (Index c : groups[gi]) {
            replace_node(at(s.m.cells, c).nodes, n, copy);
            for (Index f : at(s.m.cells, c).faces)
                replace_node(at(s.m.faces, f).nodes, n, copy);
            s.touch(c);
        }
    }
}

namespace {
// The pending faces that the current triangle (State::swept's last) can affect: those in a
// cluster of pending faces (joined through shared nodes) of which some node lies within two
// longest edges of its box. What decides whether a face is held back (the pinch of its edges:
// the tets and cut faces around their end nodes, and whether the sweep has passed all around
// them) changes only where the triangle selects, snaps and dissects, within about a cell of
// it, or sweeps, within the pinch clearance (at most a longest edge) of the nodes it frees;
// and the faces of a cluster decide together, those of different clusters apart (no face or
// tet around an edge of one has a node of another). A cluster farther away was held back by
// the previous triangle in the same state and keeps waiting untouched: each triangle then costs
// what lies near it, not every face the sweep holds back (a random soup through the 5k organ
// held back hundreds, and each triangle re-checked them all). The clusters near the faces the
// previous triangle cut are looked at again too: holding back is greedy (a face dropped for a
// pinch is not taken back in the same pass), so a cluster settles over a few triangles, and
// only one whose last look cut nothing is left as it is.
std::vector<Index> near_clusters(
    const State& s, const std::vector<Index>& faces, const geometry::Aabb& previous) {
    if (s.swept.empty())
        return faces;
    const double reach = 2 * s.max_edge;
    const auto grown = [&](geometry::Aabb b) {
        if (!b.empty()) {
            b.lo.array() -= reach;
            b.hi.array() += reach;
        }
        return b;
    };
    const geometry::Aabb box = grown(s.swept.back().box), again = grown(previous);
    const auto inside = [](const geometry::Aabb& b, const Vec3& x) {
        return !b.empty() && (x.array() >= b.lo.array()).all() && (x.array() <= b.hi.array()).all();
    };
    Dsu d(faces.size());
    std::unordered_map<Index, std::size_t> first; // node -> a face having it
    first.reserve(3 * faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i)
        for (Index n : at(s.m.faces, faces[i]).nodes)
            if (const auto [it, fresh] = first.emplace(n, i); !fresh)
                d.join(i, it->second);
    std::vector<char> hit(faces.size(), 0);
    for (std::size_t i = 0; i < faces.size(); ++i)
        for (Index n : at(s.m.faces, faces[i]).nodes)
            if (inside(box, s.X(n)) || inside(again, s.X(n)))
                hit[d.find(i)] = 1;
    std::vector<Index> out;
    for (std::size_t i = 0; i < faces.size(); ++i)
        if (hit[d.find(i)])
            out.push_back(faces[i]);
    return out;
}
} // namespace

void dissect_pending(State& s, bool everything) {
    std::unordered_set<Index> take;
    std::vector<Index> all;
    for (Index f : s.pending)
        if (!at(s.m.faces, f).boundary() && take.insert(f).second)
            all.push_back(f);
    if (all.empty()) {
        s.pending.clear();
        return;
    }
    const geometry::Aabb previous = s.last_dissected;
    s.last_dissected = {};
    std::vector<Index> order = everything ? all : near_clusters(s, all, previous);
    if (order.empty()) {
        s.pending = std::move(all);
        return;
    }
    const bool partial = order.size() < all.size();
    std::unordered_set<Index> near;
    if (partial) {
        take.clear();
        take.insert(order.begin(), order.end());
        near = take;
    }
    // Faces of far clusters stay pending, in their place in the selection order.
    const auto with_far = [&](std::vector<Index> still) {
        if (!partial)
            return still;
        const std::unordered_set<Index> now(still.begin(), still.end());
        std::vector<Index> kept;
        for (Index f : all)
            if (!near.count(f) || now.count(f))
                kept.push_back(f);
        return kept;
    };
    // Hold back faces until no edge of a taken face is pinched. Holding a face back can only
    // pinch edges at its own nodes, so only faces sharing a node with it are re-checked.
    const Pinch pinch { s, take, {}, {} };
    // Positions in `order` of the faces at each node: the newest taken face at a pinched edge
    // and the faces sharing a node with a dropped one are found among the faces at its nodes,
    // not by a pass over `order` each (a random soup held ~1,000 faces: quadratic).
    std::unordered_map<Index, std::vector<std::size_t>> at_node;
    std::vector<std::size_t> near_drop;
    auto hold_back = [&]() {
        pinch.forget(); // `take` may have changed since the last pass
        at_node.clear();
        for (std::size_t i = 0; i < order.size(); ++i)
            for (Index x : at(s.m.faces, order[i]).nodes)
                at_node[x].push_back(i);
        std::vector<Index> work(order.rbegin(), order.rend());
        while (!work.empty()) {
            const Index f = work.back();
            work.pop_back();
            if (!take.count(f))
                continue;
            const auto& loop = at(s.m.faces, f).nodes;
            for (std::size_t k = 0; k < 3; ++k) {
                const Index a = loop[k], b = loop[(k + 1) % 3];
                ++s.stats.pinch_checks;
                if (!pinch.pinched(a, b))
                    continue;
                // The newest taken face at the edge (f itself at the latest).
                std::size_t newest = 0;
                bool found = false;
                for (std::size_t i : at_node.at(a))
                    if ((!found || i > newest) && take.count(order[i])
                        && has(at(s.m.faces, order[i]).nodes, b)) {
                        newest = i;
                        found = true;
                    }
                const Index drop = order[newest];
                take.erase(drop);
                pinch.changed(drop);
                // The taken faces sharing a node with it, in the order of `order`.
                near_drop.clear();
                for (Index x : at(s.m.faces, drop).nodes)
                    for (std::size_t i : at_node.at(x))
                        if (take.count(order[i]))
                            near_drop.push_back(i);
                std::sort(near_drop.begin(), near_drop.end());
                near_drop.erase(std::unique(near_drop.begin(), near_drop.end()), near_drop.end());
                for (std::size_t i : near_drop)
                    work.push_back(order[i]);
                break;
            }
        }
    };
    hold_back();
    // Then keep small enclosed pieces attached; the faces dropped for them are not retried (a
    // later triangle would enclose the same piece), and their removal can pinch again.
    const auto before = take;
    std::vector<Index> dropped;
    const Index merged = keep_small_pieces(s, take, dropped);
    if (merged > 0) {
        hold_back();
        // If gluing a piece made another face pinch, the cut would stay open there: keep the
        // piece instead (counted as a component of its own).
        if (Index(take.size() + dropped.size()) < Index(before.size())) {
            take = before;
        } else {
            s.stats.islands_merged += merged;
            std::vector<Index> kept;
            for (Index f : order)
                if (std::find(dropped.begin(), dropped.end(), f) == dropped.end())
                    kept.push_back(f);
            order = std::move(kept);
        }
    }
    std::vector<Index> still;
    std::vector<Index> nodes;
    for (Index f : order) {
        if (!take.count(f)) {
            still.push_back(f);
            continue;
        }
        mesh::Face& face = at(s.m.faces, f);
        const Index x = face.owner, y = face.neighbour;
        mesh::Face twin;
        twin.nodes.assign(face.nodes.rbegin(), face.nodes.rend());
        twin.owner = y;
        twin.tag = mesh::FaceTag::Cut;
        twin.parent = f;
        face.neighbour = kNone;
        face.tag = mesh::FaceTag::Cut;
        nodes.insert(nodes.end(), face.nodes.begin(), face.nodes.end());
        for (Index n : face.nodes)
            s.last_dissected.extend(s.X(n));
        const Index g = s.m.num_faces();
        s.m.faces.push_back(std::move(twin));
        replace_node(at(s.m.cells, y).faces, f, g);
        s.touch(x);
        s.touch(y);
        ++s.stats.faces_dissected;
    }
    s.pending = with_far(std::move(still));
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (Index n : nodes)
        split_node(s, n);
    if (!s.pending.empty())
        open_pinches(s, false, partial ? &near : nullptr);
}

void open_pinches(State& s, bool force, const std::unordered_set<Index>* only) {
    // Pending faces whose pinched edges all lie where the sweep has passed all around, chosen
    // greedily: cutting a face can pinch only its own edges, and only cuts at a node can split
    // its star, so faces chosen earlier stay resolved by their own edge splits.
    std::unordered_set<Index> chosen;
    std::vector<Index> faces, rest;
    std::vector<std::pair<Index, Index>> edges;
    const Pinch pinch { s, chosen, {}, {} };
    for (Index f : s.pending) {
        const mesh::Face& face = at(s.m.faces, f);
        if (face.boundary())
            continue;
        if (only && !only->count(f)) {
            rest.push_back(f);
            continue;
        }
        chosen.insert(f);
        pinch.changed(f);
        std::vector<std::pair<Index, Index>> mine;
        bool ok = true;
        for (std::size_t k = 0; k < 3 && ok; ++k) {
            const Index a = face.nodes[k], b = face.nodes[(k + 1) % 3];
            ++s.stats.pinch_checks;
            if (!pinch.pinched(a, b))
                continue;
            const double r = s.opt.pinch_clearance * ring_size(s, a, b);
            ok = force || (swept_around(s, a, b, r) && swept_around(s, b, a, r));
            mine.emplace_back(std::min(a, b), std::max(a, b));
        }
        if (!ok || mine.empty()) {
            chosen.erase(f);
            pinch.changed(f);
            rest.push_back(f);
            continue;
        }
        faces.push_back(f);
        edges.insert(edges.end(), mine.begin(), mine.end());
    }
    if (faces.empty())
        return;
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    // Labels of the tets the edits reach (those of the chosen faces and around the split edges)
    // and of the tets changed earlier in the call: rebuild_faces() then makes only their faces
    // again (a whole face table per end of stroke was ~60 ms on a 26k-tet organ).
    std::vector<Index> reach;
    for (Index f : faces)
        for (Index c : { at(s.m.faces, f).owner, at(s.m.faces, f).neighbour })
            reach.push_back(c);
    for (const auto& [a, b] : edges)
        for (Index c : at(s.node_cells, a)) {
            const auto& t = at(s.m.cells, c).nodes;
            if (std::find(t.begin(), t.end(), b) != t.end())
                reach.push_back(c);
        }
    for (Index c : s.changed_cells())
        reach.push_back(c);
    std::sort(reach.begin(), reach.end());
    reach.erase(std::unique(reach.begin(), reach.end()), reach.end());
    Model md { s, {} };
    md.load_labels(reach);
    std::vector<Index> nodes;
    for (Index f : faces) {
        const mesh::Face& face = at(s.m.faces, f);
        for (Index c : { face.owner, face.neighbour }) {
            const auto& t = at(s.m.cells, c).nodes;
            for (std::size_t k = 0; k < 4; ++k)
                if (!has(face.nodes, t[k]))
                    at(md.labels, c)[k] = std::uint8_t(mesh::FaceTag::Cut);
        }
        nodes.insert(nodes.end(), face.nodes.begin(), face.nodes.end());
        for (Index n : face.nodes)
            s.last_dissected.extend(s.X(n));
        ++s.stats.faces_dissected;
    }
    for (const auto& [a, b] : edges) {
        nodes.push_back(md.split({ a, b }, 0.5 * (s.X(a) + s.X(b)), mix(s, a, b, 0.5)));
        ++s.stats.pinches_split;
    }
    s.pending = std::move(rest);
    const auto nmap = rebuild_faces(md);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (Index n : nodes)
        if (at(nmap, n) != kNone)
            split_node(s, at(nmap, n));
}

} // namespace polycut::cut::snap
