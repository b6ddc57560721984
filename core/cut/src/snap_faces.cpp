// Face table of the degeneracy-removal model: per-cell face labels loaded from the face table,
// and the face table rebuilt from tets and labels after the edits, with cells and nodes compacted
// and the per-call bookkeeping (pre-call ids, weights, moved nodes, pending faces) carried along.
#include "snap_model.hpp"

#include <map>
#include <unordered_map>

namespace polycut::cut::snap {

void Model::load_labels() {
    labels.assign(s.m.cells.size(), Labels { kInterior, kInterior, kInterior, kInterior });
    for (Index c = 0; c < s.m.num_cells(); ++c) {
        const auto& nodes = at(s.m.cells, c).nodes;
        for (Index f : at(s.m.cells, c).faces) {
            const auto& face = at(s.m.faces, f);
            for (std::size_t k = 0; k < 4; ++k)
                if (std::find(face.nodes.begin(), face.nodes.end(), nodes[k]) == face.nodes.end())
                    at(labels, c)[k] = face.boundary() ? std::uint8_t(face.tag) : kInterior;
        }
    }
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
        s.cell_volume[to] = s.cell_volume[from];
    }
    std::vector<Index> deferred;
    for (Index c : s.deferred)
        if (c < Index(cmap.size()) && at(cmap, c) != kNone)
            deferred.push_back(at(cmap, c));
    s.deferred = std::move(deferred);
    for (auto* v : { &s.cell_old, &s.cell_parent })
        v->resize(std::size_t(nc));
    s.cell_volume.resize(std::size_t(nc));
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

} // namespace polycut::cut::snap
