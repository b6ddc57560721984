// Face table of the degeneracy-removal model: per-cell face labels loaded from the face table,
// and the face table rebuilt from tets and labels after the edits, with cells and nodes compacted
// and the per-call bookkeeping (pre-call ids, weights, moved nodes, pending faces) carried along.
#include "checks.hpp"
#include "snap_model.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace polycut::cut::snap {

void Model::load_label(Index c) {
    at(labels, c) = Labels { kInterior, kInterior, kInterior, kInterior };
    const auto& nodes = at(s.m.cells, c).nodes;
    for (Index f : at(s.m.cells, c).faces) {
        const auto& face = at(s.m.faces, f);
        for (std::size_t k = 0; k < 4; ++k)
            if (std::find(face.nodes.begin(), face.nodes.end(), nodes[k]) == face.nodes.end())
                at(labels, c)[k] = face.boundary() ? std::uint8_t(face.tag) : kInterior;
    }
}

void Model::load_labels() {
    // What load_label() gives every tet, from one pass over the face table: only boundary faces
    // (each of its owner alone) carry a label other than kInterior. A pass per tet over its faces
    // chased a pointer per face (~9 ms on a 26k-tet organ, at every degeneracy removal).
    labels.assign(s.m.cells.size(), Labels { kInterior, kInterior, kInterior, kInterior });
    for (const mesh::Face& face : s.m.faces) {
        if (!face.boundary() || face.owner == kNone)
            continue;
        const auto& nodes = at(s.m.cells, face.owner).nodes;
        for (std::size_t k = 0; k < 4; ++k)
            if (std::find(face.nodes.begin(), face.nodes.end(), nodes[k]) == face.nodes.end())
                at(labels, face.owner)[k] = std::uint8_t(face.tag);
    }
}

void Model::load_labels(const std::vector<Index>& cells) {
    labels.assign(s.m.cells.size(), Labels { kUnloaded, kUnloaded, kUnloaded, kUnloaded });
    for (Index c : cells)
        load_label(c);
}

namespace {

using Key = std::array<Index, 3>;

struct KeyHash {
    std::size_t operator()(const Key& k) const {
        return std::size_t((std::uint64_t(std::uint32_t(k[0])) * 0x9E3779B97F4A7C15ull)
            ^ (std::uint64_t(std::uint32_t(k[1])) << 21)
            ^ (std::uint64_t(std::uint32_t(k[2])) << 42)
            ^ std::uint64_t(std::uint32_t(k[2]) >> 22));
    }
};

Key sorted_key(const std::vector<Index>& nodes) {
    Key k { nodes[0], nodes[1], nodes[2] };
    std::sort(k.begin(), k.end());
    return k;
}

/// Pending faces (selected, not dissected yet) by node set: ids change when faces are rebuilt.
std::vector<Key> pending_keys(const State& s) {
    std::vector<Key> pend;
    for (Index f : s.pending)
        pend.push_back(sorted_key(at(s.m.faces, f).nodes));
    return pend;
}

void find_pending(State& s, const std::vector<Key>& pend) {
    const mesh::Mesh& m = s.m;
    s.pending.clear();
    for (const auto& k : pend) {
        if (std::find(k.begin(), k.end(), kNone) != k.end())
            continue;
        for (Index c : at(s.node_cells, k[0]))
            for (Index f : at(m.cells, c).faces)
                if (sorted_key(at(m.faces, f).nodes) == k && !at(m.faces, f).boundary()
                    && std::find(s.pending.begin(), s.pending.end(), f) == s.pending.end())
                    s.pending.push_back(f);
    }
}

// What the full rebuild guarantees of the face table (checked after the local one): each tet
// lists 4 faces, each the node set of one of its local faces, each naming the tet as owner or
// neighbour; a face is Interior exactly when it has a neighbour; an interior face shares its
// node set with no other face.
void check_face_table(const mesh::Mesh& m) {
    auto fail = [](const std::string& what) {
        throw std::logic_error("snap cutter, local face rebuild: " + what);
    };
    std::unordered_map<Key, Index, KeyHash> seen;
    for (Index f = 0; f < m.num_faces(); ++f) {
        const mesh::Face& face = at(m.faces, f);
        if (face.nodes.size() != 3 || face.owner == kNone)
            fail("face " + std::to_string(f) + " is malformed");
        if ((face.neighbour != kNone) != (face.tag == mesh::FaceTag::Interior))
            fail("face " + std::to_string(f) + " has a tag that does not match its sides");
        // Two Cut faces share their nodes across a pinch not opened yet; an interior face
        // shares them with no other face.
        const auto [it, fresh] = seen.emplace(sorted_key(face.nodes), f);
        if (!fresh
            && (face.tag == mesh::FaceTag::Interior
                || at(m.faces, it->second).tag == mesh::FaceTag::Interior))
            fail("faces " + std::to_string(it->second) + " and " + std::to_string(f)
                + " share their nodes");
        for (Index c : { face.owner, face.neighbour })
            if (c != kNone) {
                const auto& faces = at(m.cells, c).faces;
                if (std::find(faces.begin(), faces.end(), f) == faces.end())
                    fail("tet " + std::to_string(c) + " does not list face " + std::to_string(f));
            }
    }
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& cell = at(m.cells, c);
        if (cell.faces.size() != 4)
            fail("tet " + std::to_string(c) + " lists " + std::to_string(cell.faces.size())
                + " faces");
        for (Index f : cell.faces) {
            const mesh::Face& face = at(m.faces, f);
            if (face.owner != c && face.neighbour != c)
                fail("face " + std::to_string(f) + " does not name tet " + std::to_string(c));
            for (Index n : face.nodes)
                if (std::find(cell.nodes.begin(), cell.nodes.end(), n) == cell.nodes.end())
                    fail(
                        "face " + std::to_string(f) + " is not a face of tet " + std::to_string(c));
        }
    }
}

/// The deferred tets under a compaction's cell map (old id -> new id, kNone: deleted).
void remap_deferred(State& s, const std::vector<Index>& cmap) {
    std::vector<Index> deferred;
    for (Index c : s.deferred)
        if (c < Index(cmap.size()) && at(cmap, c) != kNone)
            deferred.push_back(at(cmap, c));
    s.deferred = std::move(deferred);
}

// Takes the tets deleted by degeneracy removal (dead) out of the cell arrays: the last live tet
// takes the id of each, so only the moved tets change ids (the whole rebuild shifted every tet
// after the first deleted one, and the caller's model then followed all of them). Their faces
// and nodes' tet lists are renamed; the removed pre-call ids are recorded.
void drop_dead_cells(Model& md, const std::vector<Index>& dead) {
    State& s = md.s;
    mesh::Mesh& m = s.m;
    Index end = m.num_cells();
    std::vector<char> is_dead(std::size_t(end), 0);
    for (Index c : dead) {
        at(is_dead, c) = 1;
        if (at(s.cell_old, c) != kNone)
            s.removed_cells_old.push_back(at(s.cell_old, c));
    }
    s.cell_volume.resize(m.cells.size(), 0.0); // appended tets are changed: end() measures them
    std::vector<Index> cmap(static_cast<std::size_t>(end));
    std::iota(cmap.begin(), cmap.end(), Index(0));
    for (Index h : dead) { // ascending
        while (end > h && at(is_dead, end - 1))
            --end;
        if (end <= h)
            break;
        const Index L = --end; // live, above h
        md.move_cell(L, h);
        for (Index f : at(m.cells, h).faces) {
            mesh::Face& face = at(m.faces, f);
            if (face.owner == L)
                face.owner = h;
            if (face.neighbour == L)
                face.neighbour = h;
        }
        for (Index n : at(m.cells, h).nodes)
            std::replace(at(s.node_cells, n).begin(), at(s.node_cells, n).end(), L, h);
        // A moved tet is reported changed: the caller's model makes it again and sums its
        // nodes' masses again in the new cell order, as a whole rebuild would (bit for bit;
        // summed in the old order they differed in the last bits, which ElasticModel's check
        // under POLYCUT_CHECK_UNDO refused).
        if (!at(s.changed, h)) {
            at(s.changed, h) = 1;
            ++s.touched;
        }
        s.changed_list.push_back(h);
        s.grid.touch(h);
        at(cmap, L) = h;
        at(is_dead, h) = 0;
        at(is_dead, L) = 1;
    }
    while (end > 0 && at(is_dead, end - 1))
        --end;
    for (Index c : dead)
        at(cmap, c) = kNone;
    remap_deferred(s, cmap);
    md.resize_cells(end);
}

// Takes the nodes this call made and left without tets (orphans, ascending) out the same way:
// the last node takes the id of each (nodes made by the call are the last ones, so pre-call ids
// never move). Renames them in the tets, faces, weights, duplications and the pending faces'
// keys; returns the node map (old -> new id, kNone for an orphan).
std::vector<Index> drop_orphan_nodes(
    State& s, const std::vector<Index>& orphans, std::vector<Key>& pend) {
    mesh::Mesh& m = s.m;
    std::vector<Index> nmap(m.rest.size());
    std::iota(nmap.begin(), nmap.end(), Index(0));
    if (orphans.empty())
        return nmap;
    std::vector<char> is_orphan(m.rest.size(), 0);
    for (Index n : orphans) {
        at(is_orphan, n) = 1;
        at(nmap, n) = kNone;
        s.new_weights.erase(n);
    }
    Index end = m.num_nodes();
    for (Index h : orphans) {
        while (end > h && at(is_orphan, end - 1))
            --end;
        if (end <= h)
            break;
        const Index L = --end;
        at(m.rest, h) = at(m.rest, L);
        at(s.node_old, h) = at(s.node_old, L);
        at(s.node_cells, h) = std::move(at(s.node_cells, L));
        for (Index c : at(s.node_cells, h)) {
            auto& cell = at(m.cells, c);
            std::replace(cell.nodes.begin(), cell.nodes.end(), L, h);
            for (Index f : cell.faces)
                std::replace(at(m.faces, f).nodes.begin(), at(m.faces, f).nodes.end(), L, h);
        }
        if (auto it = s.new_weights.find(L); it != s.new_weights.end()) {
            s.new_weights.emplace(h, std::move(it->second));
            s.new_weights.erase(L);
        }
        at(nmap, L) = h;
        at(is_orphan, h) = 0;
        at(is_orphan, L) = 1;
    }
    while (end > 0 && at(is_orphan, end - 1))
        --end;
    m.rest.resize(std::size_t(end));
    s.node_old.resize(std::size_t(end));
    s.node_cells.resize(std::size_t(end));
    std::vector<std::pair<Index, Index>> dup;
    for (const auto& [a, b] : s.duplicated)
        if (at(nmap, a) != kNone && at(nmap, b) != kNone)
            dup.emplace_back(at(nmap, a), at(nmap, b));
    s.duplicated = std::move(dup);
    for (auto& k : pend)
        for (Index& n : k)
            n = at(nmap, n);
    return nmap;
}

// The face table after edits (opening pinches, degeneracy removal): only the changed tets' faces
// are made again, from their labels, and matched by node set among themselves and with the
// faces they had, whose other sides (unchanged tets) keep them; freed ids are reused, the rest
// filled from the end of the table. Deleted tets and the nodes the call made and left without
// tets then give their ids to the last ones (drop_dead_cells, drop_orphan_nodes). O(changed
// tets) instead of O(mesh) (issue 12 item 5; the whole rebuild after a collapse was ~12 ms on
// organ_5k). Returns false, having changed nothing, where it does not apply; else sets nmap.
bool rebuild_faces_local(Model& md, std::vector<Index>& nmap) {
    State& s = md.s;
    mesh::Mesh& m = s.m;
    if (md.journal != nullptr)
        return false;
    const Index nc = m.num_cells();
    std::vector<Index> T, dead;
    for (Index c = 0; c < nc; ++c) {
        if (!md.alive(c)) {
            dead.push_back(c);
            continue;
        }
        if (at(s.changed, c)) {
            T.push_back(c);
            if (at(md.labels, c)[0] == kUnloaded)
                return false;
        }
    }
    // A node left without tets: one the call made is dropped; a pre-call one keeps its id (as
    // in the whole rebuild: the caller's model takes it out of its unknowns).
    std::vector<Index> orphans;
    for (Index n = 0; n < m.num_nodes(); ++n)
        if (at(s.node_cells, n).empty() && at(s.node_old, n) == kNone)
            orphans.push_back(n);
    std::vector<Key> pend = pending_keys(s);
    // The faces the changed and the deleted tets had, and the unchanged tet on the other side.
    std::vector<Index> old_faces;
    for (const auto* list : { &T, &dead })
        for (Index c : *list)
            old_faces.insert(
                old_faces.end(), at(m.cells, c).faces.begin(), at(m.cells, c).faces.end());
    std::sort(old_faces.begin(), old_faces.end());
    old_faces.erase(std::unique(old_faces.begin(), old_faces.end()), old_faces.end());
    std::unordered_map<Key, std::pair<Index, Index>, KeyHash> border; // key -> (face, tet)
    for (Index f : old_faces) {
        const mesh::Face& face = at(m.faces, f);
        for (Index u : { face.owner, face.neighbour })
            if (u != kNone && md.alive(u) && !at(s.changed, u))
                border.emplace(sorted_key(face.nodes), std::make_pair(f, u));
    }
    // The changed tets' faces, matched.
    struct NewFace {
        mesh::Face face;
        Index id = kNone; ///< a kept border face's id, else assigned below
    };
    std::vector<NewFace> made;
    std::unordered_map<Key, std::size_t, KeyHash> open; // interior faces waiting for a partner
    std::vector<std::array<std::size_t, 4>> local(T.size());
    std::vector<char> kept_border(old_faces.size(), 0);
    for (std::size_t t = 0; t < T.size(); ++t) {
        const Index c = T[t];
        const auto& nodes = at(m.cells, c).nodes;
        for (std::size_t k = 0; k < 4; ++k) {
            const auto& lf = mesh::kTetFaces[std::size_t(kFaceOpposite[k])];
            std::vector<Index> loop { nodes[std::size_t(lf[0])], nodes[std::size_t(lf[1])],
                nodes[std::size_t(lf[2])] };
            const Key key = sorted_key(loop);
            const std::uint8_t l = at(md.labels, c)[k];
            if (l == kInterior) {
                if (auto it = open.find(key); it != open.end()) {
                    mesh::Face& f = made[it->second].face;
                    f.neighbour = c;
                    f.tag = mesh::FaceTag::Interior;
                    local[t][k] = it->second;
                    open.erase(it);
                    continue;
                }
                if (auto it = border.find(key); it != border.end()) {
                    // Shared with an unchanged tet: the face keeps its id and that tet's loop.
                    const auto [f, u] = it->second;
                    NewFace nf;
                    nf.face = at(m.faces, f);
                    nf.face.nodes = at(m.faces, f).owner == u ? at(m.faces, f).nodes : loop;
                    if (nf.face.owner != u) {
                        std::reverse(nf.face.nodes.begin(), nf.face.nodes.end());
                        nf.face.owner = u;
                    }
                    nf.face.neighbour = c;
                    nf.face.tag = mesh::FaceTag::Interior;
                    nf.id = f;
                    kept_border[std::size_t(std::lower_bound(old_faces.begin(), old_faces.end(), f)
                        - old_faces.begin())]
                        = 1;
                    border.erase(it);
                    local[t][k] = made.size();
                    made.push_back(std::move(nf));
                    continue;
                }
                NewFace nf;
                nf.face.nodes = std::move(loop);
                nf.face.owner = c;
                nf.face.tag = mesh::FaceTag::Cut; // becomes Interior when matched
                open.emplace(key, made.size());
                local[t][k] = made.size();
                made.push_back(std::move(nf));
            } else {
                NewFace nf;
                nf.face.nodes = std::move(loop);
                nf.face.owner = c;
                nf.face.tag = mesh::FaceTag(l);
                local[t][k] = made.size();
                made.push_back(std::move(nf));
            }
        }
    }
    // Border faces no changed tet matched: the unchanged tet keeps them as Cut faces (as the
    // full rebuild tags an interior face without a partner).
    for (const auto& [key, fu] : border) {
        const auto [f, u] = fu;
        NewFace nf;
        nf.face = at(m.faces, f);
        if (nf.face.owner != u) {
            std::reverse(nf.face.nodes.begin(), nf.face.nodes.end());
            nf.face.owner = u;
        }
        nf.face.neighbour = kNone;
        nf.face.tag = mesh::FaceTag::Cut;
        nf.id = f;
        kept_border[std::size_t(
            std::lower_bound(old_faces.begin(), old_faces.end(), f) - old_faces.begin())]
            = 1;
        made.push_back(std::move(nf));
    }
    // Ids: the freed ones first (ascending), then appended.
    std::vector<Index> free;
    for (std::size_t i = 0; i < old_faces.size(); ++i)
        if (!kept_border[i])
            free.push_back(old_faces[i]);
    std::size_t next_free = 0;
    for (NewFace& nf : made)
        if (nf.id == kNone) {
            if (next_free < free.size()) {
                nf.id = free[next_free++];
            } else {
                nf.id = m.num_faces();
                m.faces.emplace_back();
            }
        }
    for (NewFace& nf : made)
        at(m.faces, nf.id) = std::move(nf.face);
    for (std::size_t t = 0; t < T.size(); ++t) {
        auto& faces = at(m.cells, T[t]).faces;
        faces.resize(4);
        for (std::size_t k = 0; k < 4; ++k)
            faces[k] = made[local[t][k]].id;
    }
    for (Index c : dead)
        at(m.cells, c).faces.clear();
    // Ids left free: filled with the last faces of the table, from the highest hole down.
    std::vector<Index> holes(free.begin() + std::ptrdiff_t(next_free), free.end());
    while (!holes.empty()) {
        const Index last = m.num_faces() - 1;
        if (holes.back() == last) {
            holes.pop_back();
            m.faces.pop_back();
            continue;
        }
        const Index h = holes.front();
        holes.erase(holes.begin());
        mesh::Face& moved = at(m.faces, last);
        for (Index c : { moved.owner, moved.neighbour })
            if (c != kNone)
                for (Index& f : at(m.cells, c).faces)
                    if (f == last)
                        f = h;
        at(m.faces, h) = std::move(moved);
        m.faces.pop_back();
    }
    if (!dead.empty())
        drop_dead_cells(md, dead);
    nmap = drop_orphan_nodes(s, orphans, pend);
    find_pending(s, pend);
    s.compacted = true; // face ids changed: the report says so (a whole sync of the mirrors)
    if (detail::incremental_checks())
        check_face_table(m);
    return true;
}

} // namespace

// Rebuilds the face table from the tets and labels, compacts cells and nodes; returns the node
// map (old -> new id, kNone if unused).
std::vector<Index> rebuild_faces(Model& md) {
    State& s = md.s;
    mesh::Mesh& m = s.m;
    if (std::vector<Index> nmap; rebuild_faces_local(md, nmap)) {
        ++s.stats.face_tables_local;
        return nmap;
    }
    ++s.stats.face_tables_whole;
    // Tets whose labels were not loaded are unchanged: their faces give them.
    for (Index c = 0; c < m.num_cells(); ++c)
        if (md.alive(c) && at(md.labels, c)[0] == kUnloaded)
            md.load_label(c);
    // Pending faces survive by their node sets.
    std::vector<Key> pend = pending_keys(s);
    // Compact cells.
    s.cell_volume.resize(m.cells.size(), 0.0); // appended tets are changed: end() measures them
    s.invalidate_grid();
    std::vector<Index> cmap(m.cells.size(), kNone);
    Index nc = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        if (!md.alive(c)) {
            if (at(s.cell_old, c) != kNone)
                s.removed_cells_old.push_back(at(s.cell_old, c));
            continue;
        }
        at(cmap, c) = nc;
        if (nc != c)
            md.move_cell(c, nc);
        ++nc;
    }
    remap_deferred(s, cmap);
    md.resize_cells(nc);
    s.changed_list.clear(); // renumbered: listed again from the flags
    for (Index c = 0; c < nc; ++c)
        if (at(s.changed, c))
            s.changed_list.push_back(c);
    s.box.assign(std::size_t(nc), {});
    s.box_ok.assign(std::size_t(nc), 0);
    // Compact the nodes this call made and left unused. A node that existed before the call
    // keeps its id even when no tet uses it any more (a degenerate tet's collapsed node): the
    // caller's model takes such nodes out of its unknowns, and without a renumbering it updates
    // only the cells the call changed instead of rebuilding itself (a whole model per
    // degeneracy removal was ~60-80 ms on the 5k organ, issue 12 item 5).
    std::vector<char> used(m.rest.size(), 0);
    for (const auto& cell : m.cells)
        for (Index n : cell.nodes)
            at(used, n) = 1;
    for (Index n = 0; n < m.num_nodes(); ++n)
        if (at(s.node_old, n) != kNone)
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
    // Faces. The old faces' node vectors are reused: a fresh allocation per face cost more
    // than the matching.
    std::vector<mesh::Face> old = std::move(m.faces);
    m.faces.clear();
    m.faces.reserve(old.size() + 64);
    std::size_t reused = 0;
    auto add_face = [&](const std::array<Index, 3>& loop, Index owner, mesh::FaceTag tag) {
        mesh::Face f;
        if (reused < old.size())
            f.nodes = std::move(old[reused++].nodes);
        f.nodes.assign(loop.begin(), loop.end());
        f.owner = owner;
        f.tag = tag;
        at(m.cells, owner).faces.push_back(m.num_faces());
        m.faces.push_back(std::move(f));
    };
    // Interior faces waiting for their other tet, by node set.
    std::unordered_map<Key, Index, KeyHash> open;
    open.reserve(2 * m.cells.size());
    for (Index c = 0; c < m.num_cells(); ++c) {
        auto& cell = at(m.cells, c);
        cell.faces.clear();
        for (std::size_t k = 0; k < 4; ++k) {
            const auto& lf = mesh::kTetFaces[std::size_t(kFaceOpposite[k])];
            const std::array<Index, 3> loop { cell.nodes[std::size_t(lf[0])],
                cell.nodes[std::size_t(lf[1])], cell.nodes[std::size_t(lf[2])] };
            std::array<Index, 3> key = loop;
            std::sort(key.begin(), key.end());
            const std::uint8_t l = at(md.labels, c)[k];
            if (l != kInterior) {
                add_face(loop, c, mesh::FaceTag(l));
                continue;
            }
            if (auto it = open.find(key); it != open.end()) {
                const Index match = it->second;
                open.erase(it);
                at(m.faces, match).neighbour = c;
                at(m.faces, match).tag = mesh::FaceTag::Interior;
                cell.faces.push_back(match);
                continue;
            }
            open.emplace(key, m.num_faces());
            add_face(loop, c, mesh::FaceTag::Cut); // becomes Interior when matched
        }
    }
    s.node_cells = m.node_cells();
    find_pending(s, pend);
    s.compacted = true;
    return nmap;
}

} // namespace polycut::cut::snap
