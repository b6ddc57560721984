// Edits of the degeneracy-removal model (002 sec. 3.2.3, Fig. 3.8-3.9): edge and face splits,
// edge collapses with validity checks (positive tets, each interior face shared by exactly two
// tets, a manifold boundary around the merged node, a rest volume budget), and cutting an
// incollapsible tet free.
#include "snap_model.hpp"

#include <cmath>
#include <map>
#include <numeric>

namespace polycut::cut::snap {

Weights mix(const State& s, Index a, Index b, double t) {
    std::map<Index, double> sum;
    for (const auto& [n, w] : s.weights_of(a))
        sum[n] += (1 - t) * w;
    for (const auto& [n, w] : s.weights_of(b))
        sum[n] += t * w;
    return { sum.begin(), sum.end() };
}

bool Model::cut_free(Index c) {
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

void Model::note_cell(Index c) {
    if (!journal || c >= journal->cells || at(journal->cell_noted, c))
        return;
    at(journal->cell_noted, c) = 1;
    journal->cells_before.push_back(
        { c, at(s.m.cells, c).nodes, at(labels, c), char(at(s.changed, c)) });
}

void Model::note_node(Index n) {
    if (!journal || n >= journal->nodes || at(journal->node_noted, n))
        return;
    at(journal->node_noted, n) = 1;
    journal->node_cells_before.emplace_back(n, at(s.node_cells, n));
}

void Model::begin_journal(Journal& j) {
    j = Journal {};
    j.cells = s.m.num_cells();
    j.nodes = s.m.num_nodes();
    j.cell_noted.assign(std::size_t(j.cells), 0);
    j.node_noted.assign(std::size_t(j.nodes), 0);
    journal = &j;
}

void Model::undo_journal(Journal& j) {
    journal = nullptr;
    for (Index n = j.nodes; n < s.m.num_nodes(); ++n)
        s.new_weights.erase(n);
    s.m.rest.resize(std::size_t(j.nodes));
    s.node_old.resize(std::size_t(j.nodes));
    s.node_cells.resize(std::size_t(j.nodes));
    for (auto& [n, cells] : j.node_cells_before)
        at(s.node_cells, n) = std::move(cells);
    resize_cells(j.cells);
    for (auto& old : j.cells_before) {
        at(s.m.cells, old.c).nodes = std::move(old.nodes);
        at(labels, old.c) = old.labels;
        at(s.changed, old.c) = old.changed;
        at(s.box_ok, old.c) = 0;
    }
}

void Model::set_cell(Index c, const Tet& t) {
    note_cell(c);
    auto& nodes = at(s.m.cells, c).nodes;
    for (Index n : nodes) {
        note_node(n);
        std::erase(at(s.node_cells, n), c);
    }
    nodes.assign(t.begin(), t.end());
    for (Index n : nodes) {
        note_node(n);
        at(s.node_cells, n).push_back(c);
    }
    s.touch(c);
}

void Model::move_cell(Index from, Index to) {
    at(s.m.cells, to) = std::move(at(s.m.cells, from));
    at(labels, to) = at(labels, from);
    at(s.marks, to) = at(s.marks, from);
    at(s.selected, to) = at(s.selected, from);
    at(s.changed, to) = at(s.changed, from);
    at(s.cell_old, to) = at(s.cell_old, from);
    at(s.cell_parent, to) = at(s.cell_parent, from);
    if (std::size_t(from) < s.cell_volume.size() && std::size_t(to) < s.cell_volume.size())
        at(s.cell_volume, to) = at(s.cell_volume, from);
    at(s.box, to) = at(s.box, from);
    at(s.box_ok, to) = at(s.box_ok, from);
}

void Model::resize_cells(Index n) {
    const auto k = std::size_t(n);
    s.m.cells.resize(k);
    labels.resize(k);
    s.marks.resize(k);
    s.selected.resize(k);
    s.changed.resize(k);
    s.cell_old.resize(k);
    s.cell_parent.resize(k);
    s.cell_volume.resize(std::min(k, s.cell_volume.size())); // end() measures the rest
    s.box.resize(k);
    s.box_ok.resize(k);
}

void Model::kill(Index c) {
    note_cell(c);
    for (Index n : at(s.m.cells, c).nodes) {
        note_node(n);
        std::erase(at(s.node_cells, n), c);
    }
    at(s.m.cells, c).nodes.clear();
    at(s.changed, c) = 0;
}

Index Model::add_cell(const Tet& t, const Labels& l, Index parent) {
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

Index Model::split(const std::vector<Index>& sigma, const Vec3& Xm, const Weights& w) {
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
                note_cell(c);
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

bool Model::collapse(Index u, Index v, const Vec3& Xu) {
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
        note_cell(c);
        at(labels, c) = lab[c];
        at(s.marks, c) = { -1, -1, -1, -1, -1, -1 };
        set_cell(c, t);
    }
    ++s.stats.edges_collapsed;
    return true;
}

} // namespace polycut::cut::snap
