#include "editor.hpp"

#include "checks.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace polycut::cut::detail {

Editor::Editor(mesh::Mesh& mesh, const CutOptions& options)
    : m(mesh)
    , opt(options) {
    rebuild();
    double volume = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        volume += std::abs(m.cell_volume(c));
    m_cell_size = m.num_cells() > 0 ? std::cbrt(volume / double(m.num_cells())) : 0.0;
    // cells_near()'s grid now, with the reach split_along_triangle asks for: the pipeline makes
    // its cutter at load (CutPipeline::prepare), so the first cut of a stroke does not pay it.
    build_grid();
}

void Editor::rebuild() {
    node_cells = m.node_cells();
    const std::size_t nc = m.cells.size();
    m_bounds.assign(nc, {});
    m_bounds_ok.assign(nc, 0);
    m_thickness.assign(nc, std::numeric_limits<double>::quiet_NaN());
    m_changed.assign(nc, 0);
    m_changed_list.clear();
    m_grid.invalidate();
}

void Editor::renumber(const std::vector<Index>& cell_map) {
    m_grid.renumber(cell_map);
    const std::size_t nc = m.cells.size();
    std::vector<geometry::Aabb> bounds(nc);
    std::vector<char> bounds_ok(nc, 0);
    std::vector<double> thickness(nc, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t c = 0; c < std::min(cell_map.size(), m_bounds.size()); ++c)
        if (const Index to = cell_map[c]; to != kNone && std::size_t(to) < nc) {
            bounds[std::size_t(to)] = m_bounds[c];
            bounds_ok[std::size_t(to)] = m_bounds_ok[c];
            thickness[std::size_t(to)] = m_thickness[c];
        }
    m_bounds = std::move(bounds);
    m_bounds_ok = std::move(bounds_ok);
    m_thickness = std::move(thickness);
    // The adjacency follows the map in place: a removed cell leaves the lists, the others take
    // their new ids, and each list sorted is what m.node_cells() gives (cells in id order),
    // without making every node's list again (that was two thirds of merge_slivers on the
    // 5k organ; perf).
    node_cells.resize(m.rest.size());
    for (std::vector<Index>& list : node_cells) {
        std::size_t k = 0;
        for (const Index c : list)
            if (const Index to
                = std::size_t(c) < cell_map.size() ? cell_map[std::size_t(c)] : kNone;
                to != kNone)
                list[k++] = to;
        list.resize(k);
        std::sort(list.begin(), list.end());
    }
    if (incremental_checks() && node_cells != m.node_cells())
        throw Error("cut", "node adjacency after renumbering cells differs from the mesh's");
    m_changed.assign(nc, 0);
    m_changed_list.clear();
}

void Editor::begin(CutReport& r) {
    report = &r;
    r = CutReport {};
    r.nodes_before = m.num_nodes();
    r.cells_before = m.num_cells();
    r.faces_before = Index(m.faces.size());
    m_changed.assign(m.cells.size(), 0);
    m_changed_list.clear();
}

void Editor::end() {
    CutReport& r = *report;
    std::sort(m_changed_list.begin(), m_changed_list.end());
    for (Index c : m_changed_list)
        m.classify_cell(c);
    r.changed_cells = m_changed_list;
    r.nodes_after = m.num_nodes();
    r.cells_after = m.num_cells();
    r.topology_changed = !m_changed_list.empty() || !r.cut_faces.empty();
    r.pattern_changed = r.nodes_after != r.nodes_before || r.cells_after != r.cells_before
        || !m_changed_list.empty();
    report = nullptr;
}

void Editor::move_node(Index n, const Vec3& X) {
    // A node this call made is new to the caller: only existing nodes are reported as moved.
    auto& moved = report->moved_nodes;
    if (n < report->nodes_before
        && std::none_of(moved.begin(), moved.end(), [n](const auto& e) { return e.first == n; }))
        moved.emplace_back(n, at(m.rest, n));
    at(m.rest, n) = X;
    for (Index c : at(node_cells, n))
        touch(c);
}

void Editor::touch(Index c) {
    if (std::size_t(c) >= m_changed.size()) {
        m_changed.resize(m.cells.size(), 0);
        m_bounds.resize(m.cells.size());
        m_bounds_ok.resize(m.cells.size(), 0);
        m_thickness.resize(m.cells.size(), std::numeric_limits<double>::quiet_NaN());
    }
    at(m_bounds_ok, c) = 0;
    at(m_thickness, c) = std::numeric_limits<double>::quiet_NaN();
    m_grid.touch(c);
    if (!at(m_changed, c)) {
        at(m_changed, c) = 1;
        m_changed_list.push_back(c);
    }
}

const geometry::Aabb& Editor::bounds(Index c) {
    if (std::size_t(c) >= m_bounds.size())
        touch(c);
    if (!at(m_bounds_ok, c)) {
        geometry::Aabb box;
        for (Index n : at(m.cells, c).nodes)
            box.extend(at(m.rest, n));
        at(m_bounds, c) = box;
        at(m_bounds_ok, c) = 1;
    }
    return at(m_bounds, c);
}

void Editor::build_grid() {
    const double reach = kSweepReach * opt.snap;
    m_grid.build(m.num_cells(), [&](Index c) {
        geometry::Aabb b = bounds(c);
        const double r = reach * (b.hi - b.lo).norm();
        b.lo.array() -= r;
        b.hi.array() += r;
        return b;
    });
}

const std::vector<Index>& Editor::cells_near(const geometry::Aabb& box, Index limit) {
    if (m_grid.stale(m.num_cells()))
        build_grid();
    return m_grid.query(box, limit);
}

double Editor::thickness(Index c) {
    if (std::size_t(c) >= m_thickness.size())
        touch(c);
    double& h = at(m_thickness, c);
    if (std::isnan(h)) {
        double area = 0;
        for (Index f : at(m.cells, c).faces)
            area += geometry::polygon_area(geometry::gather(m.rest, at(m.faces, f).nodes));
        const double v = std::abs(m.cell_volume(c));
        h = area > 0 ? 6.0 * v / area : 0.0;
    }
    return h;
}

double Editor::snap_eps(Index n) {
    double h = std::numeric_limits<double>::infinity();
    for (Index c : at(node_cells, n))
        h = std::min(h, thickness(c));
    return std::isfinite(h) ? opt.snap * h : 0.0;
}

Weights Editor::weights_of(Index n) const {
    if (!report || n < report->nodes_before)
        return { { n, 1.0 } };
    return at(report->new_nodes, n - report->nodes_before).weights;
}

Index Editor::add_node(const Vec3& X, Weights weights, Index parent_cell, NodeOrigin::Kind kind) {
    const Index id = m.num_nodes();
    m.rest.push_back(X);
    node_cells.emplace_back();
    NodeOrigin o;
    o.node = id;
    o.kind = kind;
    o.parent_cell = parent_cell;
    o.weights = std::move(weights);
    report->new_nodes.push_back(std::move(o));
    return id;
}

namespace {
Weights blend(const Weights& a, double wa, const Weights& b, double wb) {
    std::map<Index, double> sum;
    for (const auto& [n, w] : a)
        sum[n] += wa * w;
    for (const auto& [n, w] : b)
        sum[n] += wb * w;
    Weights out;
    for (const auto& [n, w] : sum)
        if (w != 0)
            out.emplace_back(n, w);
    return out;
}
} // namespace

Index Editor::split_edge(Index a, Index b, double t, Index parent_cell) {
    t = std::clamp(t, 0.0, 1.0);
    const Vec3 X = (1 - t) * at(m.rest, a) + t * at(m.rest, b);
    const Index mid = add_node(
        X, blend(weights_of(a), 1 - t, weights_of(b), t), parent_cell, NodeOrigin::Kind::Edge);
    // Every cell around the edge uses both end nodes; insert the node into each face loop where
    // a and b are consecutive (each global face once, whichever cell reaches it first).
    std::vector<Index> around;
    for (Index c : at(node_cells, a)) {
        const auto& cb = at(node_cells, b);
        if (std::find(cb.begin(), cb.end(), c) != cb.end())
            around.push_back(c);
    }
    for (Index c : around) {
        bool uses = false;
        for (Index f : at(m.cells, c).faces) {
            auto& loop = at(m.faces, f).nodes;
            const std::size_t k = loop.size();
            for (std::size_t i = 0; i < k; ++i) {
                const Index u = loop[i], v = loop[(i + 1) % k];
                if ((u == a && v == b) || (u == b && v == a)) {
                    loop.insert(loop.begin() + std::ptrdiff_t(i + 1), mid);
                    uses = true;
                    break;
                }
                if (u == mid)
                    uses = true;
            }
        }
        if (uses) {
            at(m.cells, c).nodes.push_back(mid);
            at(node_cells, mid).push_back(c);
            touch(c);
        }
    }
    return mid;
}

Index Editor::add_face(mesh::Face face) {
    const Index id = m.num_faces();
    m.faces.push_back(std::move(face));
    const mesh::Face& f = m.faces.back();
    at(m.cells, f.owner).faces.push_back(id);
    touch(f.owner);
    if (f.neighbour != kNone) {
        at(m.cells, f.neighbour).faces.push_back(id);
        touch(f.neighbour);
    }
    return id;
}

Index Editor::split_face(Index f, std::vector<Index> keep, std::vector<Index> other) {
    mesh::Face g = at(m.faces, f);
    at(m.faces, f).nodes = std::move(keep);
    g.nodes = std::move(other);
    g.parent = f;
    return add_face(std::move(g));
}

void Editor::refresh_cell_nodes(Index c) {
    mesh::Cell& cell = at(m.cells, c);
    std::vector<Index> nodes;
    for (Index f : cell.faces)
        for (Index n : at(m.faces, f).nodes)
            nodes.push_back(n);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (Index n : cell.nodes)
        if (!std::binary_search(nodes.begin(), nodes.end(), n)) {
            auto& nc = at(node_cells, n);
            nc.erase(std::remove(nc.begin(), nc.end(), c), nc.end());
        }
    for (Index n : nodes) {
        auto& nc = at(node_cells, n);
        if (std::find(nc.begin(), nc.end(), c) == nc.end())
            nc.push_back(c);
    }
    cell.nodes = std::move(nodes);
    touch(c);
}

int find_in(const std::vector<Index>& loop, Index v) {
    for (std::size_t i = 0; i < loop.size(); ++i)
        if (loop[i] == v)
            return int(i);
    return -1;
}

bool clean_pattern(const std::vector<int>& s) {
    const int k = int(s.size());
    std::vector<int> nz; // positions of nonzero signs
    for (int i = 0; i < k; ++i)
        if (s[std::size_t(i)] != 0)
            nz.push_back(i);
    if (nz.size() < 2)
        return true;
    int changes = 0;
    for (std::size_t j = 0; j < nz.size(); ++j) {
        const int i0 = nz[j], i1 = nz[(j + 1) % nz.size()];
        if (s[std::size_t(i0)] != s[std::size_t(i1)]) {
            ++changes;
            const int gap = (i1 - i0 - 1 + k) % k; // zeros between them
            if (gap > 1)
                return false;
        }
    }
    return changes == 0 || changes == 2;
}

void split_loop(const std::vector<Index>& loop, const std::vector<int>& s, std::vector<Index>& plus,
    std::vector<Index>& minus) {
    const std::size_t k = loop.size();
    // Start of the + arc: a + whose previous node is a zero preceded by a -... find a + node
    // whose predecessor is 0 and for which walking back over zeros reaches a -.
    std::size_t start = k;
    for (std::size_t i = 0; i < k && start == k; ++i) {
        if (s[i] != 1)
            continue;
        std::size_t j = (i + k - 1) % k;
        if (s[j] != 0)
            continue;
        std::size_t back = (j + k - 1) % k;
        if (s[back] == -1)
            start = j;
    }
    plus.clear();
    minus.clear();
    if (start == k)
        return;
    std::size_t i = start;
    plus.push_back(loop[i]);
    i = (i + 1) % k;
    while (s[i] != -1) {
        plus.push_back(loop[i]);
        i = (i + 1) % k;
    }
    const std::size_t end = (i + k - 1) % k; // the zero before the - arc
    for (std::size_t j = end;; j = (j + 1) % k) {
        minus.push_back(loop[j]);
        if (j == start)
            break;
    }
}

std::vector<Index> compact_faces(mesh::Mesh& m, const std::vector<char>& dead) {
    // In place from the first dead face on: a cut's merged faces are among the newest, so on an
    // organ the faces before them (most of ~55k) keep their ids and are not moved; this was a
    // copy of the whole face table per merging call (issue 12 item 5).
    const std::size_t n = m.faces.size();
    std::size_t first = 0;
    while (first < n && !dead[first])
        ++first;
    std::vector<Index> face_map(n, kNone);
    std::iota(face_map.begin(), face_map.begin() + std::ptrdiff_t(first), Index(0));
    if (first == n)
        return face_map;
    std::size_t kept = first;
    for (std::size_t f = first; f < n; ++f)
        if (!dead[f]) {
            face_map[f] = Index(kept);
            if (kept != f)
                m.faces[kept] = std::move(m.faces[f]);
            ++kept;
        }
    m.faces.resize(kept);
    const Index moved = Index(first); // ids below it are unchanged
    for (mesh::Face& face : m.faces)
        if (face.parent >= moved)
            face.parent
                = face.parent < Index(face_map.size()) ? face_map[std::size_t(face.parent)] : kNone;
    for (mesh::Cell& cell : m.cells)
        for (Index& f : cell.faces)
            if (f >= moved)
                f = face_map[std::size_t(f)];
    return face_map;
}

} // namespace polycut::cut::detail
