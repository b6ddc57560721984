// sim::Simulation::cut: world-space sweep triangles to rest space, the cut itself, and the state
// transfer that keeps new nodes where the material was (nothing pops, 000 sec. 5.1).
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/cut/completeness.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace polycut::sim {
namespace {
geometry::Aabb triangle_box(const std::array<Vec3, 3>& t) {
    geometry::Aabb b;
    for (const Vec3& p : t)
        b.extend(p);
    return b;
}

/// The snapping rule for blades in planes of faces (issue 12 item 2): a blade meant to run in a
/// plane of mesh faces (a grid plane, an earlier cut's face) arrives a few micrometres off it
/// after the world-to-rest fit of a deforming body, and cutting there would leave sheets of
/// cells microns thick (they explode in the next step) or, for face snapping, no crossings at
/// all. When every corner of rest triangle `r` lies within `tol` [m] of the plane of a face of
/// the cells `near`, the corners not yet fixed by earlier triangles (`known` false) are
/// projected onto the closest such plane, provided the fixed ones already lie in it (within
/// `exact` [m]). One outcome per configuration, no jitter and no retry.
void snap_to_face_plane(const mesh::Mesh& m, const std::vector<Index>& near, std::array<Vec3, 3>& r,
    const std::array<bool, 3>& known, double tol, double exact) {
    double best = tol;
    Vec3 best_n = Vec3::Zero();
    double best_d = 0;
    std::set<Index> seen;
    for (Index c : near)
        for (Index f : m.cells[std::size_t(c)].faces) {
            if (!seen.insert(f).second)
                continue;
            const std::vector<Vec3> loop = geometry::gather(m.rest, m.faces[std::size_t(f)].nodes);
            const Vec3 n = geometry::polygon_normal(loop);
            if (!(n.norm() > 0.5))
                continue;
            const double d = n.dot(geometry::polygon_centroid(loop));
            double worst = 0;
            bool fixed_ok = true;
            for (std::size_t k = 0; k < 3; ++k) {
                const double dist = std::abs(n.dot(r[k]) - d);
                worst = std::max(worst, dist);
                fixed_ok = fixed_ok && (!known[k] || dist <= exact);
            }
            if (fixed_ok && worst <= best && worst > 0) {
                best = worst;
                best_n = n;
                best_d = d;
            }
        }
    if (best_n.isZero())
        return;
    for (std::size_t k = 0; k < 3; ++k)
        if (!known[k])
            r[k] -= (best_n.dot(r[k]) - best_d) * best_n;
}

/// The snapping rule for the blade's edges (issue 12 item 2, docs/decisions/0007): a new corner
/// `x` of a rest sweep triangle with unit normal `n` and offset `d0` that lies within `tol` [m]
/// of a node of the uncut mesh `m` in the triangle's plane goes onto that node; otherwise,
/// within `tol` of the chord the plane cuts from a face of the uncut mesh (an edge when the
/// edge lies in the plane), onto that chord. The triangle's
/// plane does not change. A blade meant to run along grid edges or through grid nodes (its tip,
/// the start and the end of a stroke) arrives ~0.2 mm beside them after the affine fit of a
/// sagging body; cut there, it left strips of faces and nodes that close whose cells had
/// near-zero-energy modes. `cells`: the cells of `m` near x; `in_plane` [m]: how close to the
/// plane a node counts as in it. Only the uncut mesh's features attract: the nodes the stroke
/// itself made would pull each new corner back onto the previous crack front.
void snap_corner_to_features(const mesh::Mesh& m, const std::vector<Index>& cells, Vec3& x,
    const Vec3& n, double d0, double tol, double in_plane) {
    double best_node = tol, best_chord = tol;
    Vec3 node_target = x, chord_target = x;
    std::vector<Vec3> ends;
    for (Index c : cells)
        for (Index f : m.cells[std::size_t(c)].faces) {
            // The chord the plane cuts from the face (an edge of it when the edge lies in the
            // plane); faces in the plane have none.
            const auto& loop = m.faces[std::size_t(f)].nodes;
            ends.clear();
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const Vec3& a = m.rest[std::size_t(loop[i])];
                const Vec3& b = m.rest[std::size_t(loop[(i + 1) % loop.size()])];
                const double da = n.dot(a) - d0, db = n.dot(b) - d0;
                if (std::abs(da) <= in_plane) {
                    ends.push_back(a);
                    if ((a - x).norm() < best_node) {
                        best_node = (a - x).norm();
                        node_target = a;
                    }
                } else if (std::abs(db) > in_plane && (da < 0) != (db < 0)) {
                    ends.push_back(a + (da / (da - db)) * (b - a));
                }
            }
            if (ends.size() != 2)
                continue;
            const Vec3 e = ends[1] - ends[0];
            if (!(e.squaredNorm() > 0))
                continue;
            const Vec3 p
                = ends[0] + std::clamp((x - ends[0]).dot(e) / e.squaredNorm(), 0.0, 1.0) * e;
            if ((p - x).norm() < best_chord) {
                best_chord = (p - x).norm();
                chord_target = p;
            }
        }
    if (best_node < tol)
        x = node_target;
    else if (best_chord < tol)
        x = chord_target;
}
} // namespace

CutSummary Simulation::cut(const std::vector<std::array<Vec3, 3>>& world) {
    Impl& s = *m_impl;
    Stopwatch watch;
    CutSummary summary;
    summary.cells_before = s.mesh.num_cells();
    // Validate everything before anything changes.
    if (world.empty())
        throw InputError("triangles", "needs at least one sweep triangle");
    geometry::Aabb tissue;
    for (const Vec3& p : s.positions)
        tissue.extend(p);
    const double L = tissue.diagonal();
    for (std::size_t t = 0; t < world.size(); ++t) {
        const std::string where = "triangles/" + std::to_string(t);
        for (std::size_t k = 0; k < 3; ++k) {
            if (!world[t][k].allFinite())
                throw InputError(where + "/" + std::to_string(k), "must be finite");
            if ((world[t][k] - tissue.center()).norm() > 1e3 * L)
                throw InputError(
                    where + "/" + std::to_string(k), "is absurdly far from the tissue");
        }
    }
    const bool snap = s.scene.cutting.method == "snap";
    if (snap && !s.snap_cutter) {
        cut::SnapOptions opt;
        s.snap_cutter = std::make_unique<cut::SnapCutter>(s.mesh, opt);
    } else if (!snap && !s.cutter) {
        cut::CutOptions opt;
        opt.snap = s.scene.cutting.snap_distance;
        opt.sliver_volume = s.scene.cutting.sliver_volume;
        s.cutter = std::make_unique<cut::Cutter>(s.mesh, opt);
    }
    // World to rest (DESIGN.md sec. 3): each triangle through ONE least-squares affine fit of the
    // nodes of the cells whose deformed bounds it touches (found through a uniform grid over the
    // deformed cell bounds, refitted once per call). cut::WorldToRest maps each corner
    // through its own cell instead; for sweeps whose corners lie far outside the tissue that
    // extrapolates from single boundary cells and tilts the plane (cut_slices merged its 1 mm
    // slices), so the joint fit stays until WorldToRest clips triangles to the tissue first. Exact
    // where the deformation is affine over those cells (always at rest).
    // Corners shared with earlier triangles of the stroke (the blade's previous position, the
    // diagonal of a swept quad) reuse their rest image, so consecutive triangles meet exactly in
    // rest space instead of differing by two fits. The new corners of such a triangle are put
    // onto its predecessor's rest plane when they lie within kStrokePlane x (mean cell size) of
    // it: a straight stroke through a deforming tissue is then one rest plane, as it would be at
    // rest, and does not re-split the cells along its crack into slivers every tick (the fits of
    // successive ticks differ by a small fraction of a cell). A curved stroke leaves the plane
    // as soon as it bends by more than that.
    constexpr double kStrokePlane = 0.05;
    // A blade whose rest triangle lies within kFacePlane x (mean cell size) of the plane of a
    // face of the cells it meets is put into that plane (see snap_to_face_plane).
    constexpr double kFacePlane = 0.02;
    // A new corner within kEdgeSnap x (mean cell size) of a node of the uncut mesh or of the
    // chord its plane cuts from a face goes onto it (see snap_corner_to_features).
    constexpr double kEdgeSnap = 0.05;
    // Below this area (relative to L^2) or altitude (relative to L) a triangle cuts nothing; the
    // cutter rejects such rest triangles (CutOptions::min_area), so they are dropped here first.
    constexpr double kMinSweepArea = 2 * cut::CutOptions {}.min_area;
    const double cell_size = s.initial_cell_size; // tolerances do not shrink as cuts add cells
    const double same = 1e-9 * L;
    auto cached = [&](const Vec3& p) -> const Impl::StrokeCorner* {
        for (const Impl::StrokeCorner& c : s.stroke_corners)
            if ((c.world - p).norm() <= same)
                return &c;
        return nullptr;
    };
    if (!s.locator)
        s.locator = std::make_unique<cut::WorldToRest>(s.mesh);
    bool located = false; // the grid is refitted once per call, when first needed
    if (!s.rest_locator) { // the uncut mesh at rest: built once
        s.rest_locator = std::make_unique<cut::WorldToRest>(s.initial_mesh);
        s.rest_locator->refit(s.initial_mesh.rest, false);
    }
    std::vector<cut::Triangle> rest;
    for (const auto& tri : world) {
        // A sliver of a sweep (the blade barely moved between two samples) cuts nothing at the
        // tissue's scale: skipped, not an error, so a slow stroke is never rejected for it.
        const double area = 0.5 * (tri[1] - tri[0]).cross(tri[2] - tri[0]).norm();
        if (!(area > kMinSweepArea * L * L)) {
            ++summary.triangles_skipped;
            continue;
        }
        cut::Triangle r;
        std::array<bool, 3> known {};
        const Impl::StrokeCorner* previous = nullptr;
        for (std::size_t k = 0; k < 3; ++k)
            if (const Impl::StrokeCorner* c = cached(tri[k])) {
                r[k] = c->rest;
                known[k] = true;
                previous = previous ? previous : c;
            }
        if (!(known[0] && known[1] && known[2])) {
            const geometry::Aabb tb = triangle_box(tri);
            std::set<Index> nodes;
            if (!located) {
                s.locator->refit(s.positions, false);
                located = true;
            }
            const std::vector<Index> near = s.locator->candidates(tb);
            for (Index c : near)
                nodes.insert(s.mesh.cells[std::size_t(c)].nodes.begin(),
                    s.mesh.cells[std::size_t(c)].nodes.end());
            if (nodes.size() < 4)
                continue; // outside the tissue: nothing to cut
            std::vector<Vec3> X, x;
            for (Index n : nodes) {
                X.push_back(s.mesh.rest[std::size_t(n)]);
                x.push_back(s.positions[std::size_t(n)]);
            }
            const geometry::AffineFit fit = geometry::fit_affine(X, x);
            if (!fit.ok || std::abs(fit.A.determinant()) < 1e-12)
                continue;
            const Mat3 Ainv = fit.A.inverse();
            for (std::size_t k = 0; k < 3; ++k)
                if (!known[k]) {
                    r[k] = Ainv * (tri[k] - fit.t);
                    if (previous) {
                        // In the previous triangle's plane in world space (a straight stroke),
                        // or close to its rest plane: onto that rest plane. The first test
                        // does not depend on the fit, which extrapolates for corners outside
                        // the tissue and errs by a few percent of a cell on a sagging body.
                        const double dw
                            = previous->world_normal.dot(tri[k]) - previous->world_offset;
                        const double d = previous->normal.dot(r[k]) - previous->offset;
                        if (std::abs(dw) <= kStrokePlane * cell_size
                            || std::abs(d) <= kStrokePlane * cell_size)
                            r[k] -= d * previous->normal;
                    }
                }
            snap_to_face_plane(s.mesh, near, r, known, kFacePlane * cell_size, same);
            // Cell splitting only: face snapping moves nodes onto the blade itself.
            const Vec3 rn = (r[1] - r[0]).cross(r[2] - r[0]).normalized();
            for (std::size_t k = 0; k < 3 && !snap; ++k) {
                if (known[k] || !rn.allFinite())
                    continue;
                geometry::Aabb around;
                around.extend(r[k] - Vec3::Constant(kEdgeSnap * cell_size));
                around.extend(r[k] + Vec3::Constant(kEdgeSnap * cell_size));
                snap_corner_to_features(s.initial_mesh, s.rest_locator->candidates(around), r[k],
                    rn, rn.dot(r[(k + 1) % 3]), kEdgeSnap * cell_size, same);
            }
        }
        const Vec3 normal = (r[1] - r[0]).cross(r[2] - r[0]);
        const double longest
            = std::max({ (r[1] - r[0]).norm(), (r[2] - r[1]).norm(), (r[0] - r[2]).norm() });
        if (!(0.5 * normal.norm() > kMinSweepArea * L * L)
            || !(normal.norm() / longest > kMinSweepArea * L)) {
            ++summary.triangles_skipped; // collapsed in rest space: nothing to cut
            continue;
        }
        const Vec3 n = normal.normalized();
        const Vec3 world_n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
        for (std::size_t k = 0; k < 3; ++k)
            if (!known[k])
                s.stroke_corners.push_back(
                    { tri[k], r[k], n, n.dot(r[k]), world_n, world_n.dot(tri[k]) });
        rest.push_back(r);
    }
    // Only the recent corners can be shared by the next triangles.
    constexpr std::size_t kKeep = 64;
    if (s.stroke_corners.size() > kKeep)
        s.stroke_corners.erase(
            s.stroke_corners.begin(), s.stroke_corners.end() - std::ptrdiff_t(kKeep));
    if (rest.empty()) {
        summary.cut_ms = watch.ms();
        summary.cells_after = s.mesh.num_cells();
        return summary;
    }
    // A cut is all or nothing: if the cutter or the model update fails on some configuration
    // (a cell the basis cannot handle), the mesh and the state go back to what they were and the
    // error is reported; the simulation keeps running on the uncut mesh.
    Impl::Snapshot before = s.snapshot();
    try {
        const cut::CutReport report = snap ? s.snap_cutter->cut(rest) : s.cutter->cut(rest);
        summary.triangles_applied = int(report.triangles - report.triangles_missed);
        summary.cells_split = int(report.new_cells.size());
        summary.nodes_added = int(report.nodes_after - report.nodes_before);
        summary.topology_changed = report.topology_changed;
        for (const cut::Triangle& t : rest)
            summary.swept_area
                += cut::area_inside(s.initial_mesh, s.rest_locator->candidates(triangle_box(t)), t);
        if (report.topology_changed) {
            s.resize_state_after_cut(report);
            s.check_cut_cells(report.changed_cells);
            if (is_static())
                summary.pieces_fixed = s.fix_free_pieces();
        }
    } catch (const std::exception& e) {
        s.restore(before);
        throw Error(
            "cut", std::string("failed and was undone, the mesh is unchanged: ") + e.what());
    }
    // Until the next step shows the cut model is sound, the state before the first cut of this
    // tick stays at hand (Simulation::step undoes the cut when that step fails).
    if (summary.topology_changed && !s.cut_undo)
        s.cut_undo = std::make_unique<Impl::Snapshot>(std::move(before));
    s.swept_area += summary.swept_area;
    summary.cells_after = s.mesh.num_cells();
    summary.cut_ms = watch.ms();
    return summary;
}

void Simulation::Impl::check_cut_cells(const std::vector<Index>& cells) const {
    // Mechanical sanity of what the cut made (issue 12 item 3): every changed cell encloses a
    // positive rest volume (the model update has already checked that each has an affine fit).
    for (Index c : cells) {
        if (c < 0 || c >= mesh.num_cells())
            continue;
        const double v = mesh.cell_volume(c);
        if (!(v > 0) || !std::isfinite(v))
            throw Error("cut",
                "cell " + std::to_string(c) + " has rest volume " + std::to_string(v)
                    + " m^3 after the cut");
    }
}

double Simulation::blade_min_advance() const {
    const Impl& s = *m_impl;
    if (s.scene.cutting.method == "snap")
        return 0.0;
    constexpr double kMinAdvance = 0.25; // of the mean cell size
    return kMinAdvance * s.initial_cell_size;
}

void Simulation::end_stroke() {
    Impl& s = *m_impl;
    s.stroke_corners.clear();
    if (!s.snap_cutter)
        return;
    // Face snapping holds faces back while cutting them would pinch an edge; when the blade is
    // lifted they are cut (their pinched edges split), so the stroke ends complete.
    Impl::Snapshot before = s.snapshot();
    try {
        const cut::CutReport report = s.snap_cutter->finish_sweep();
        if (!report.topology_changed)
            return;
        s.resize_state_after_cut(report);
        s.check_cut_cells(report.changed_cells);
        if (is_static())
            s.fix_free_pieces();
    } catch (const std::exception& e) {
        s.restore(before);
        throw Error("cut", std::string("finishing the stroke failed and was undone: ") + e.what());
    }
    if (!s.cut_undo)
        s.cut_undo = std::make_unique<Impl::Snapshot>(std::move(before));
}

void Simulation::Impl::resize_state_after_cut(const cut::CutReport& report) {
    const Index n_old = report.nodes_before, n_new = report.nodes_after;
    // Surviving nodes keep their state (renumbered by node_map when the snap cutter compacted
    // nodes); new nodes take displacement and velocity from the material they came from.
    const MatX3 x_old = state.x, v_old = state.v;
    const std::vector<std::uint8_t> fixed_old = node_fixed_mask;
    const VecX loads_old = scene_forces;
    state.x = MatX3::Zero(n_new, 3);
    state.v = MatX3::Zero(n_new, 3);
    node_fixed_mask.assign(3 * std::size_t(n_new), 0);
    scene_forces = VecX::Zero(3 * n_new);
    auto new_id
        = [&](Index i) { return report.node_map.empty() ? i : report.node_map[std::size_t(i)]; };
    for (Index i = 0; i < n_old; ++i) {
        const Index j = new_id(i);
        if (j == kNone)
            continue;
        state.x.row(j) = x_old.row(i);
        state.v.row(j) = v_old.row(i);
        scene_forces.segment<3>(3 * j) = loads_old.segment<3>(3 * i);
        for (std::size_t k = 0; k < 3; ++k)
            node_fixed_mask[3 * std::size_t(j) + k] = fixed_old[3 * std::size_t(i) + k];
    }
    // Forces and grabs follow their material nodes.
    auto remap = [&](NodeWeights& at) {
        NodeWeights out;
        double total = 0;
        for (std::size_t k = 0; k < at.nodes.size(); ++k)
            if (const Index j = new_id(at.nodes[k]); j != kNone) {
                out.nodes.push_back(j);
                out.weights.push_back(at.weights[k]);
                total += at.weights[k];
            }
        for (double& w : out.weights)
            w /= total > 0 ? total : 1.0;
        at = out;
    };
    if (!report.node_map.empty()) {
        for (auto& [id, f] : forces)
            remap(f.at);
        for (auto& [id, g] : grabs)
            remap(g.at);
    }
    for (const cut::NodeOrigin& o : report.new_nodes) {
        Vec3 x = Vec3::Zero(), v = Vec3::Zero();
        std::array<bool, 3> fixed { true, true, true };
        for (const auto& [n, w] : o.weights) {
            x += w * x_old.row(n).transpose();
            v += w * v_old.row(n).transpose();
            for (int k = 0; k < 3; ++k)
                fixed[std::size_t(k)]
                    = fixed[std::size_t(k)] && fixed_old[3 * std::size_t(n) + std::size_t(k)];
        }
        state.x.row(o.node) = x.transpose();
        state.v.row(o.node) = v.transpose();
        // A node between fixed nodes (on a fixed face) is fixed too, per component.
        for (int k = 0; k < 3; ++k)
            node_fixed_mask[3 * std::size_t(o.node) + std::size_t(k)]
                = o.weights.empty() ? 0 : fixed[std::size_t(k)];
    }
    // Nodes the snap cutter moved in rest space keep their displacement (the material point
    // moved by the snap distance, a fraction of a cell; 002 sec. 3.2.2 snaps in the reference
    // configuration for the same reason).
    for (const auto& [node, old_rest] : report.moved_nodes)
        state.x.row(node) += (mesh.rest[std::size_t(node)] - old_rest).transpose();
    if (!report.removed_cells.empty() || !report.node_map.empty())
        model->rebuild_topology();
    else
        model->update_cells(report.changed_cells);
    model->set_fixed_dofs(node_fixed_mask);
    static_solved = false;
    sync_positions();
    refresh_topology();
}

Simulation::Impl::Snapshot Simulation::Impl::snapshot() const {
    Snapshot snap { {}, state, node_fixed_mask, scene_forces, forces, grabs, swept_area, topology,
        topology_version };
    mesh::pack(mesh, snap.mesh);
    return snap;
}

void Simulation::Impl::restore(const Snapshot& snap, bool published) {
    mesh = mesh::unpack(snap.mesh);
    state = snap.state;
    node_fixed_mask = snap.node_fixed_mask;
    scene_forces = snap.scene_forces;
    forces = snap.forces;
    grabs = snap.grabs;
    swept_area = snap.swept_area;
    // The cutters' adjacency and remembered sweeps refer to the failed edit: start them afresh.
    cutter.reset();
    snap_cutter.reset();
    stroke_corners.clear();
    model->rebuild_topology();
    model->set_fixed_dofs(node_fixed_mask);
    static_solved = false;
    sync_positions();
    topology = snap.topology;
    topology_version = published ? topology_version + 1 : snap.topology_version;
}

int Simulation::Impl::fix_free_pieces() {
    // Connected pieces of cells through shared nodes (union-find over cells).
    const Index nc = mesh.num_cells();
    std::vector<Index> root(std::size_t(nc), kNone);
    for (Index c = 0; c < nc; ++c)
        root[std::size_t(c)] = c;
    auto find = [&](Index c) {
        while (root[std::size_t(c)] != c)
            c = root[std::size_t(c)] = root[std::size_t(root[std::size_t(c)])];
        return c;
    };
    std::vector<Index> node_cell(std::size_t(mesh.num_nodes()), kNone);
    for (Index c = 0; c < nc; ++c)
        for (Index n : mesh.cells[std::size_t(c)].nodes) {
            Index& first = node_cell[std::size_t(n)];
            if (first == kNone)
                first = c;
            else
                root[std::size_t(find(c))] = find(first);
        }
    std::vector<char> anchored(std::size_t(nc), 0);
    for (Index c = 0; c < nc; ++c)
        for (Index n : mesh.cells[std::size_t(c)].nodes)
            for (std::size_t k = 0; k < 3; ++k)
                if (node_fixed_mask[3 * std::size_t(n) + k])
                    anchored[std::size_t(find(c))] = 1;
    // Each free piece: fix the nodes of its largest boundary face.
    std::vector<Index> face_of(std::size_t(nc), kNone);
    std::vector<double> area_of(std::size_t(nc), 0.0);
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        if (!face.boundary())
            continue;
        const Index r = find(face.owner);
        if (anchored[std::size_t(r)])
            continue;
        const double a = geometry::polygon_area(geometry::gather(mesh.rest, face.nodes));
        if (a > area_of[std::size_t(r)]) {
            area_of[std::size_t(r)] = a;
            face_of[std::size_t(r)] = f;
        }
    }
    int fixed = 0;
    for (Index r = 0; r < nc; ++r) {
        if (face_of[std::size_t(r)] == kNone)
            continue;
        for (Index n : mesh.faces[std::size_t(face_of[std::size_t(r)])].nodes)
            for (std::size_t k = 0; k < 3; ++k)
                node_fixed_mask[3 * std::size_t(n) + k] = 1;
        ++fixed;
    }
    if (fixed > 0)
        model->set_fixed_dofs(node_fixed_mask);
    return fixed;
}

} // namespace polycut::sim
