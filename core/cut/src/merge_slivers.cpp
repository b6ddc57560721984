// Sliver removal by merging (000 sec. 4). A cut that passes just beyond the snapping distance of
// a cell's nodes leaves a cell of nearly zero volume next to a normal one; its basis gradients
// blow up and so does the condition number. Seed 000 projects the sliver onto its plane and
// reconnects the neighbours; we merge it with the face neighbour whose union with it is convex
// (up to CutOptions::convex_tol), which removes it in the same local way while conserving the
// rest volume exactly (no node moves) and keeping every face planar. Only interior faces are
// merged across: the material stays separated along Cut faces.
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace polycut::cut::detail {
namespace {

// Faces of the union of cells a and b: both face lists without the faces they share.
std::vector<Index> union_faces(const mesh::Mesh& m, Index a, Index b) {
    std::vector<Index> out;
    for (Index c : { a, b })
        for (Index f : at(m.cells, c).faces) {
            const mesh::Face& face = at(m.faces, f);
            const bool shared = (face.owner == a && face.neighbour == b)
                || (face.owner == b && face.neighbour == a);
            if (!shared)
                out.push_back(f);
        }
    return out;
}

// True when the union's outward face loops form a closed 2-manifold: every directed edge once and
// its reverse once (a sliver separated from its neighbour by a crack elsewhere would fold).
bool closed_manifold(const mesh::Mesh& m, Index a, Index b, const std::vector<Index>& faces) {
    std::map<std::pair<Index, Index>, int> directed;
    for (Index f : faces) {
        const mesh::Face& face = at(m.faces, f);
        const bool owned = face.owner == a || face.owner == b;
        const auto& l = face.nodes;
        for (std::size_t i = 0; i < l.size(); ++i) {
            const Index u = l[i], v = l[(i + 1) % l.size()];
            if (++directed[owned ? std::make_pair(u, v) : std::make_pair(v, u)] > 1)
                return false;
        }
    }
    for (const auto& [e, count] : directed)
        if (!directed.count({ e.second, e.first }))
            return false;
    return true;
}

// Largest distance of a node of the union outside one of its face planes, relative to the
// union's bounding-box diagonal (the measure of check_cut_invariants).
double convexity_violation(const mesh::Mesh& m, Index a, Index b, const std::vector<Index>& faces) {
    std::vector<Index> nodes;
    for (Index f : faces)
        nodes.insert(nodes.end(), at(m.faces, f).nodes.begin(), at(m.faces, f).nodes.end());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    geometry::Aabb box;
    for (Index n : nodes)
        box.extend(at(m.rest, n));
    double worst = 0;
    for (Index f : faces) {
        const mesh::Face& face = at(m.faces, f);
        // Outward for the union: the loop is outward for its owner, a or b, or reversed.
        const bool owned = face.owner == a || face.owner == b;
        const auto pts = geometry::gather(m.rest, face.nodes);
        const Vec3 nrm = (owned ? 1.0 : -1.0) * geometry::polygon_normal(pts);
        const Vec3 ctr = geometry::polygon_centroid(pts);
        for (Index n : nodes)
            worst = std::max(worst, (at(m.rest, n) - ctr).dot(nrm));
    }
    const double diag = box.diagonal();
    return diag > 0 ? worst / diag : std::numeric_limits<double>::infinity();
}

// Merges cell `gone` into cell `keep` (their shared faces disappear). Leaves `gone` empty.
void merge_into(Editor& ed, Index keep, Index gone, std::vector<char>& dead_face) {
    mesh::Mesh& m = ed.m;
    const std::vector<Index> faces = union_faces(m, keep, gone);
    for (Index f : at(m.cells, keep).faces)
        if (std::find(faces.begin(), faces.end(), f) == faces.end())
            dead_face[std::size_t(f)] = 1;
    for (Index f : faces) {
        mesh::Face& face = at(m.faces, f);
        if (face.owner == gone)
            face.owner = keep;
        if (face.neighbour == gone)
            face.neighbour = keep;
    }
    at(m.cells, keep).faces = faces;
    for (Index n : at(m.cells, gone).nodes) {
        auto& nc = at(ed.node_cells, n);
        nc.erase(std::remove(nc.begin(), nc.end(), gone), nc.end());
    }
    at(m.cells, gone).faces.clear();
    at(m.cells, gone).nodes.clear();
    ed.refresh_cell_nodes(keep);
    at(m.cells, keep).shape = mesh::CellShape::Polyhedron;
}
} // namespace

// Largest convexity violation of a merged cell, relative to its diagonal: unions that are
// convex up to round-off (a sliver with its sibling, a slab with the block beside it).
constexpr double kConvexUnion = 1e-9;

void merge_slivers(Editor& ed) {
    if (!ed.opt.merge_slivers || !(ed.opt.sliver_volume > 0))
        return;
    mesh::Mesh& m = ed.m;
    CutReport& r = *ed.report;
    const std::vector<Index> candidates = ed.changed_cells();
    std::vector<std::pair<double, Index>> slivers; // (volume, cell), smallest first
    for (Index c : candidates) {
        const double v = m.cell_volume(c);
        double largest = 0;
        for (Index f : at(m.cells, c).faces) {
            const mesh::Face& face = at(m.faces, f);
            if (face.tag == mesh::FaceTag::Interior)
                largest = std::max(
                    largest, m.cell_volume(face.owner == c ? face.neighbour : face.owner));
        }
        if (v < ed.opt.sliver_volume * largest)
            slivers.emplace_back(v, c);
    }
    if (slivers.empty())
        return;
    std::sort(slivers.begin(), slivers.end());

    std::vector<char> dead_cell(m.cells.size(), 0), dead_face(m.faces.size(), 0);
    std::vector<Index> merged_into(m.cells.size(), kNone);
    for (const auto& [v, c] : slivers) {
        if (dead_cell[std::size_t(c)])
            continue;
        Index best = kNone;
        // The cutter's plane splits assume convex cells: only (numerically) convex unions.
        double best_violation = kConvexUnion;
        for (Index f : at(m.cells, c).faces) {
            const mesh::Face& face = at(m.faces, f);
            if (face.tag != mesh::FaceTag::Interior)
                continue;
            const Index n = face.owner == c ? face.neighbour : face.owner;
            if (n == best || dead_cell[std::size_t(n)])
                continue;
            const std::vector<Index> faces = union_faces(m, c, n);
            if (!closed_manifold(m, c, n, faces))
                continue;
            const double violation = convexity_violation(m, c, n, faces);
            if (violation < best_violation) {
                best_violation = violation;
                best = n;
            }
        }
        if (best == kNone) {
            ++r.slivers_kept;
            continue;
        }
        merge_into(ed, best, c, dead_face);
        dead_cell[std::size_t(c)] = 1;
        merged_into[std::size_t(c)] = best;
        ++r.slivers_merged;
    }
    if (r.slivers_merged == 0)
        return;
    const std::vector<Index> touched = ed.changed_cells();

    // Compact faces, then cells; renumber everything that refers to them.
    const std::vector<Index> face_map = compact_faces(m, dead_face);
    r.faces_renumbered = true;
    std::vector<Index> cell_map(m.cells.size(), kNone);
    std::vector<mesh::Cell> cells;
    for (std::size_t c = 0; c < m.cells.size(); ++c)
        if (!dead_cell[c]) {
            cell_map[c] = Index(cells.size());
            cells.push_back(std::move(m.cells[c]));
        } else if (Index(c) < r.cells_before) {
            r.removed_cells.push_back(Index(c));
        }
    for (mesh::Face& face : m.faces) {
        face.owner = cell_map[std::size_t(face.owner)];
        if (face.neighbour != kNone)
            face.neighbour = cell_map[std::size_t(face.neighbour)];
    }
    for (mesh::Cell& cell : cells)
        if (cell.parent != kNone && cell.parent < Index(cell_map.size()))
            cell.parent = cell_map[std::size_t(cell.parent)];
    m.cells = std::move(cells);
    auto map_cell = [&](Index c) { return c == kNone ? kNone : cell_map[std::size_t(c)]; };
    // A cell merged away lives on in the cell it was merged into (chains followed).
    auto survivor = [&](Index c) {
        while (c != kNone && dead_cell[std::size_t(c)])
            c = merged_into[std::size_t(c)];
        return map_cell(c);
    };
    r.cell_map = cell_map;
    r.cell_map.resize(std::size_t(r.cells_before)); // old ids only
    std::vector<CellOrigin> new_cells;
    for (const CellOrigin& o : r.new_cells)
        if (const Index c = map_cell(o.cell); c != kNone)
            new_cells.push_back({ c, o.parent });
    r.new_cells = std::move(new_cells);
    for (NodeOrigin& o : r.new_nodes)
        o.parent_cell = survivor(o.parent_cell);
    std::vector<Index> cut_faces;
    for (Index f : r.cut_faces)
        if (const Index g = face_map[std::size_t(f)]; g != kNone)
            cut_faces.push_back(g);
    r.cut_faces = std::move(cut_faces);
    std::vector<Index> changed;
    for (Index c : touched)
        if (const Index d = map_cell(c); d != kNone)
            changed.push_back(d);
    // The adjacency and caches refer to old ids: renumber them, then mark the changed cells.
    ed.renumber(cell_map);
    for (Index c : changed)
        ed.touch(c);
}

} // namespace polycut::cut::detail
