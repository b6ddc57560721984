// SnapCutter: input validation, the per-triangle pipeline of 002 sec. 3.2 (select, snap, dissect,
// remove degeneracies) and the per-call bookkeeping that becomes the CutReport.
#include "checks.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/cut/fault_injection.hpp"
#include "snap_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace polycut::cut {

double tet_aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // 002 sec. 3.2.3: min over nodes of the distance to the opposite face plane, over the longest
    // edge. The smallest height is 3 V / (largest face area).
    const double V = (b - a).dot((c - a).cross(d - a)) / 6.0;
    const double areas[4] = { 0.5 * (c - b).cross(d - b).norm(), 0.5 * (c - a).cross(d - a).norm(),
        0.5 * (b - a).cross(d - a).norm(), 0.5 * (b - a).cross(c - a).norm() };
    const double amax = *std::max_element(std::begin(areas), std::end(areas));
    const double emax = std::max({ (b - a).norm(), (c - a).norm(), (d - a).norm(), (c - b).norm(),
        (d - b).norm(), (d - c).norm() });
    if (!(amax > 0) || !(emax > 0))
        return 0;
    return 3.0 * V / (amax * emax);
}

std::array<double, 6> tet_dihedral_angles(
    const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const std::array<Vec3, 4> p { a, b, c, d };
    // Outward normal of the face opposite node k.
    std::array<Vec3, 4> n;
    for (int k = 0; k < 4; ++k) {
        std::array<int, 3> o {};
        int j = 0;
        for (int i = 0; i < 4; ++i)
            if (i != k)
                o[std::size_t(j++)] = i;
        Vec3 v = (p[std::size_t(o[1])] - p[std::size_t(o[0])])
                     .cross(p[std::size_t(o[2])] - p[std::size_t(o[0])]);
        if (v.dot(p[std::size_t(k)] - p[std::size_t(o[0])]) > 0)
            v = -v;
        const double len = v.norm();
        n[std::size_t(k)] = len > 0 ? Vec3(v / len) : Vec3::Zero();
    }
    std::array<double, 6> out {};
    for (std::size_t e = 0; e < 6; ++e) {
        // The edge (i, j) is shared by the faces opposite the two other nodes.
        const auto [i, j] = snap::kTetEdges[e];
        std::array<int, 2> kl {};
        int t = 0;
        for (int k = 0; k < 4; ++k)
            if (k != i && k != j)
                kl[std::size_t(t++)] = k;
        const double cosang
            = std::clamp(n[std::size_t(kl[0])].dot(n[std::size_t(kl[1])]), -1.0, 1.0);
        out[e] = std::numbers::pi - std::acos(cosang);
    }
    return out;
}

namespace snap {

double tet_volume(const mesh::Mesh& m, Index c) {
    const auto& t = m.cells[std::size_t(c)].nodes;
    const Vec3& a = m.rest[std::size_t(t[0])];
    return (m.rest[std::size_t(t[1])] - a)
               .dot((m.rest[std::size_t(t[2])] - a).cross(m.rest[std::size_t(t[3])] - a))
        / 6.0;
}

double tet_mesh_volume(const mesh::Mesh& m) {
    // Sum of tet volumes from the node lists: no face loops, no allocation.
    double v = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        v += tet_volume(m, c);
    return v;
}

State::State(mesh::Mesh& mesh, const SnapOptions& options)
    : m(mesh)
    , opt(options) {
    rebuild();
}

void State::rebuild() {
    geometry::Aabb all;
    for (const Vec3& x : m.rest)
        all.extend(x);
    L = std::max(all.diagonal(), 1e-300);
    center = all.empty() ? Vec3::Zero() : all.center();
    cell_volume.resize(m.cells.size());
    volume0 = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        volume0 += at(cell_volume, c) = tet_volume(m, c);
    volume_now = volume0;
    max_edge = 0;
    for (const mesh::Cell& c : m.cells)
        for (std::size_t i = 0; i < c.nodes.size(); ++i)
            for (std::size_t j = i + 1; j < c.nodes.size(); ++j)
                max_edge = std::max(max_edge, (X(c.nodes[i]) - X(c.nodes[j])).norm());
    node_cells = m.node_cells();
    marks.assign(m.cells.size(), { -1, -1, -1, -1, -1, -1 });
    selected.assign(m.cells.size(), 0);
    deferred.clear();
    pending.clear();
    last_dissected = {};
    recent.clear();
    swept.clear();
    box.assign(m.cells.size(), {});
    box_ok.assign(m.cells.size(), 0);
    // The grid now (at load, CutPipeline::prepare()), not in the first cut's tick.
    grid.build(m.num_cells(), [&](Index c) { return bounds(c); });
}

void State::begin(CutReport& r) {
    report = &r;
    r = CutReport {};
    stats = SnapStats {};
    r.nodes_before = m.num_nodes();
    r.cells_before = m.num_cells();
    r.volume_before = volume_now; // what the previous call ended with (the mesh is ours)
    node_old.resize(m.rest.size());
    for (std::size_t i = 0; i < node_old.size(); ++i)
        node_old[i] = Index(i);
    cell_old.resize(m.cells.size());
    for (std::size_t i = 0; i < cell_old.size(); ++i)
        cell_old[i] = Index(i);
    cell_parent.assign(m.cells.size(), kNone);
    new_weights.clear();
    moved_from.clear();
    changed.assign(m.cells.size(), 0);
    changed_list.clear();
    touched = 0;
    sweep_tests = 0;
    duplicated.clear();
    removed_cells_old.clear();
    removed_nodes_old.clear();
    compacted = false;
}

void State::end() {
    CutReport& r = *report;
    stats.sweep_tests = sweep_tests;
    r.nodes_after = m.num_nodes();
    r.cells_after = m.num_cells();
    // The volume from the cache: only the changed tets are measured again (every edit of a
    // tet's nodes or of a node's position touches the tet; rebuild_faces() moves the entries).
    cell_volume.resize(m.cells.size(), 0.0);
    for (Index c = 0; c < m.num_cells(); ++c)
        if (at(changed, c))
            at(cell_volume, c) = tet_volume(m, c);
    double volume = 0;
    for (double v : cell_volume)
        volume += v;
    if (detail::incremental_checks() && volume != tet_mesh_volume(m))
        throw std::logic_error("snap cutter: cached tet volumes differ from the mesh's ("
            + std::to_string(volume) + " vs " + std::to_string(tet_mesh_volume(m)) + " m^3)");
    r.volume_after = volume_now = volume;
    r.faces_renumbered = compacted;
    for (Index n = 0; n < m.num_nodes(); ++n) {
        if (at(node_old, n) != kNone)
            continue;
        NodeOrigin o;
        o.node = n;
        o.kind = NodeOrigin::Kind::Edge;
        o.parent_cell = at(node_cells, n).empty() ? kNone : at(node_cells, n).front();
        o.weights = new_weights.at(n);
        if (o.weights.size() == 1)
            o.kind = NodeOrigin::Kind::Duplicate;
        r.new_nodes.push_back(std::move(o));
    }
    r.duplicated = duplicated;
    for (Index c = 0; c < m.num_cells(); ++c) {
        if (!at(changed, c))
            continue;
        r.changed_cells.push_back(c);
        if (at(cell_old, c) == kNone)
            r.new_cells.push_back({ c, at(cell_parent, c) });
    }
    if (!removed_cells_old.empty()) {
        r.cell_map.assign(std::size_t(r.cells_before), kNone);
        for (Index c = 0; c < m.num_cells(); ++c)
            if (at(cell_old, c) != kNone)
                at(r.cell_map, at(cell_old, c)) = c;
        r.removed_cells = removed_cells_old;
        std::sort(r.removed_cells.begin(), r.removed_cells.end());
    }
    if (!removed_nodes_old.empty()) {
        r.node_map.assign(std::size_t(r.nodes_before), kNone);
        for (Index n = 0; n < m.num_nodes(); ++n)
            if (at(node_old, n) != kNone)
                at(r.node_map, at(node_old, n)) = n;
        r.removed_nodes = removed_nodes_old;
        std::sort(r.removed_nodes.begin(), r.removed_nodes.end());
    }
    for (const auto& [n, X0] : moved_from)
        if ((at(m.rest, n) - X0).norm() > 0)
            r.moved_nodes.emplace_back(n, X0);
    std::sort(r.moved_nodes.begin(), r.moved_nodes.end(),
        [](const auto& a, const auto& b) { return a.first < b.first; });
    for (Index c : r.changed_cells)
        for (Index f : at(m.cells, c).faces)
            if (at(m.faces, f).tag == mesh::FaceTag::Cut)
                r.cut_faces.push_back(f);
    std::sort(r.cut_faces.begin(), r.cut_faces.end());
    r.cut_faces.erase(std::unique(r.cut_faces.begin(), r.cut_faces.end()), r.cut_faces.end());
    r.slivers_merged = Index(r.removed_cells.size());
    r.topology_changed = !r.changed_cells.empty();
    r.pattern_changed = r.nodes_after != r.nodes_before || r.cells_after != r.cells_before
        || !r.duplicated.empty() || !r.removed_nodes.empty();
    stats.faces_pending = Index(pending.size());
    stats.volume_change
        = r.volume_before > 0 ? std::abs(r.volume_after - r.volume_before) / r.volume_before : 0;
    report = nullptr;
}

const geometry::Aabb& State::bounds(Index c) {
    if (!at(box_ok, c)) {
        geometry::Aabb b;
        for (Index n : at(m.cells, c).nodes)
            b.extend(at(m.rest, n));
        at(box, c) = b;
        at(box_ok, c) = 1;
    }
    return at(box, c);
}

void State::touch(Index c) {
    at(box_ok, c) = 0;
    grid.touch(c);
    if (!at(changed, c)) {
        ++touched;
        changed_list.push_back(c);
    }
    at(changed, c) = 1;
}

std::vector<Index> State::changed_cells() const {
    std::vector<Index> out;
    for (Index c : changed_list)
        if (c < Index(changed.size()) && at(changed, c))
            out.push_back(c);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void State::move_node(Index n, const Vec3& Xn) {
    if (at(node_old, n) != kNone)
        moved_from.try_emplace(n, at(m.rest, n));
    at(m.rest, n) = Xn;
    for (Index c : at(node_cells, n))
        touch(c);
}

Index State::add_node(const Vec3& Xn, Weights w) {
    const Index n = m.num_nodes();
    m.rest.push_back(Xn);
    node_cells.emplace_back();
    node_old.push_back(kNone);
    new_weights.emplace(n, std::move(w));
    return n;
}

Weights State::weights_of(Index n) const {
    if (at(node_old, n) != kNone)
        return { { at(node_old, n), 1.0 } };
    return new_weights.at(n);
}

Index State::global_face(Index c, int lf) const {
    const auto& nodes = at(m.cells, c).nodes;
    std::array<Index, 3> key {};
    for (std::size_t i = 0; i < 3; ++i)
        key[i] = nodes[std::size_t(mesh::kTetFaces[std::size_t(lf)][i])];
    std::sort(key.begin(), key.end());
    for (Index f : at(m.cells, c).faces) {
        const auto& fn = at(m.faces, f).nodes;
        if (fn.size() != 3)
            continue;
        std::array<Index, 3> k2 { fn[0], fn[1], fn[2] };
        std::sort(k2.begin(), k2.end());
        if (k2 == key)
            return f;
    }
    return kNone;
}

double State::aspect(Index c, Index n, const Vec3& Xn) const {
    std::array<Vec3, 4> p;
    const auto& nodes = at(m.cells, c).nodes;
    for (std::size_t i = 0; i < 4; ++i)
        p[i] = nodes[i] == n ? Xn : X(nodes[i]);
    return tet_aspect_ratio(p[0], p[1], p[2], p[3]);
}

} // namespace snap

struct SnapCutter::Impl {
    Impl(mesh::Mesh& mesh, const SnapOptions& o)
        : s(mesh, o) { }
    snap::State s;

    void validate(std::span<const Triangle> tris) const {
        const double L = s.L;
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const std::string where = "triangle " + std::to_string(i);
            const Triangle& t = tris[i];
            for (const Vec3& p : t) {
                if (!p.allFinite())
                    throw InputError(where, "non-finite coordinate");
                if ((p - s.center).norm() > s.opt.max_extent * L)
                    throw InputError(where, "coordinate too far from the tissue");
            }
            const double area = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
            const double longest
                = std::max({ (t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm() });
            if (!(area > s.opt.min_area * L * L) || !(2 * area / longest > s.opt.min_area * L))
                throw InputError(
                    where, "degenerate triangle (area " + std::to_string(area) + " m^2)");
        }
    }
};

namespace {
void check_tets(const mesh::Mesh& m) {
    for (Index c = 0; c < m.num_cells(); ++c)
        if (m.cells[std::size_t(c)].shape != mesh::CellShape::Tet)
            throw InputError("cell " + std::to_string(c),
                "face snapping (method `tet`) needs a pure tetrahedral mesh");
}
} // namespace

SnapCutter::SnapCutter(mesh::Mesh& mesh, SnapOptions options) {
    check_tets(mesh);
    if (!(options.degenerate_aspect >= 0) || !(options.snap_min_aspect >= 0)
        || !(options.plane_eps >= 0) || !(options.large_dihedral > 0))
        throw InputError("options", "negative or NaN tolerance");
    m_impl = std::make_unique<Impl>(mesh, options);
}

SnapCutter::~SnapCutter() = default;

void SnapCutter::end_sweep() {
    auto& s = m_impl->s;
    s.marks.assign(s.m.cells.size(), { -1, -1, -1, -1, -1, -1 });
    s.selected.assign(s.m.cells.size(), 0);
    s.deferred.clear();
    s.pending.clear();
    s.last_dissected = {};
    s.recent.clear();
    s.swept.clear();
    s.swept_memo.clear();
}

CutReport SnapCutter::finish_sweep() {
    Stopwatch watch;
    auto& s = m_impl->s;
    CutReport report;
    s.begin(report);
    if (!s.pending.empty()) {
        // Every face held back is looked at once more (each triangle looked only at those it
        // could have freed), then the ones still pinched are cut with their edges split.
        snap::dissect_pending(s, true);
        if (!s.pending.empty())
            snap::open_pinches(s, true);
    }
    s.end();
    end_sweep();
    report.elapsed_ms = watch.ms();
    return report;
}

void SnapCutter::rebuild() {
    check_tets(m_impl->s.m);
    m_impl->s.rebuild();
}

CutReport SnapCutter::remove_degeneracies() {
    Stopwatch watch;
    auto& s = m_impl->s;
    CutReport report;
    s.begin(report);
    snap::remove_degeneracies(s, true);
    s.end();
    if (report.topology_changed)
        end_sweep();
    report.elapsed_ms = watch.ms();
    return report;
}

const SnapStats& SnapCutter::stats() const {
    return m_impl->s.stats;
}
const SnapOptions& SnapCutter::options() const {
    return m_impl->s.opt;
}
const mesh::Mesh& SnapCutter::mesh() const {
    return m_impl->s.m;
}

namespace {
/// The call's work so far in tet equivalents (CutReport::work): the cells it touched, its pinch
/// checks and its tests against the sweep (snap_cutter.hpp), which grow with the faces held back
/// and the length of the sweep: a random soup's 16-triangle calls took 140-170 ms while they
/// touched 30-160 cells.
double work(const snap::State& s) {
    return double(s.touched) + double(s.stats.pinch_checks) / double(kPinchChecksPerWork)
        + double(s.sweep_tests) / double(kSweepTestsPerWork);
}
} // namespace

CutReport SnapCutter::cut(std::span<const Triangle> rest_triangles, Index max_changed_cells) {
    Stopwatch watch;
    m_impl->validate(rest_triangles);
    auto& s = m_impl->s;
    CutReport report;
    s.begin(report);
    for (const Triangle& tri : rest_triangles) {
        ++report.triangles;
        snap::SweepPlane plane;
        plane.tri = tri;
        plane.normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
        plane.offset = plane.normal.dot(tri[0]);
        for (const Vec3& p : tri)
            plane.box.extend(p);
        s.swept.push_back(plane);
        const Index crossed = s.stats.edges_crossed;
        auto faces = snap::select_faces(s, plane);
        if (s.stats.edges_crossed == crossed)
            ++report.triangles_missed;
        const auto retried = snap::retry_deferred(s, plane);
        faces.insert(faces.end(), retried.begin(), retried.end());
        for (int round = 0; round < 8 && s.opt.snap_nodes && !faces.empty(); ++round) {
            const auto moved = snap::snap_face_nodes(s, plane, faces);
            faces = snap::mark_snapped_nodes(s, plane, moved);
        }
        if (s.opt.snap_nodes) {
            // Then the faces of the swept surface that 002's per-tet rule has not reached
            // (docs/decisions/0008).
            auto moved = snap::select_swept_faces(s, plane);
            for (int round = 0; round < 8 && !moved.empty(); ++round)
                moved = snap::snap_face_nodes(s, plane, snap::mark_snapped_nodes(s, plane, moved));
        }
        // Faces snapped into the plane of an earlier triangle by this one are selected too.
        if (s.recent.size() == 4)
            s.recent.erase(s.recent.begin());
        s.recent.push_back(plane);
        for (const auto& p : s.recent)
            snap::select_faces_in_plane(s, p);
        snap::dissect_pending(s);
        if (s.opt.remove_degeneracies)
            snap::remove_degeneracies(s);
        if (max_changed_cells > 0 && work(s) >= double(max_changed_cells))
            break;
    }
    detail::fail_if_injected();
    report.work = work(s);
    s.end();
    report.elapsed_ms = watch.ms();
    return report;
}

} // namespace polycut::cut
