// sim::Simulation::cut: core/cut's pipeline (validation, world to rest, the cut), then the state
// transfer that keeps new nodes where the material was (nothing pops, 000 sec. 5.1) and the
// undo of a cut that cannot be carried.
#include "build_clock.hpp"
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/cut/completeness.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <unordered_map>

namespace polycut::sim {

CutSummary Simulation::cut(const std::vector<std::array<Vec3, 3>>& world, int max_triangles) {
    Impl& s = *m_impl;
    Stopwatch watch;
    CutSummary summary;
    summary.cells_before = summary.cells_after = int(s.mesh.num_cells());
    const Index budget = s.scene.cutting.max_cells_per_tick;
    // Each call is charged what it does over the whole model besides the cells it cuts: a tick
    // that cut already takes another call (a second stroke, a `cut` after carried triangles) only
    // while the budget left pays for that. The tick's first call always runs (every stroke
    // advances); two calls of a nearly full budget were the organ's worst split tick (decision
    // 0076).
    const Index call_cost = budget > 0 ? cut_call_cost(s.mesh) : 0;
    const bool cut_this_tick = s.cut_cells_left < budget;
    if (budget > 0 && !world.empty()
        && (s.cut_cells_left <= 0 || (cut_this_tick && s.cut_cells_left < call_cost))) {
        // This tick's cuts have used the budget: everything waits for the next tick.
        summary.status = CutSummary::Status::Deferred;
        summary.triangles_deferred = int(world.size());
        return summary;
    }
    s.ensure_cutting();
    std::unique_ptr<Impl::Snapshot> before;
    cut::CutResult result = s.cutting->cut(
        world, s.positions, budget > 0 ? s.cut_cells_left : 0, [&] { before = s.take_snapshot(); },
        std::size_t(std::max(0, max_triangles)));
    if (budget > 0)
        s.cut_cells_left -= call_cost;
    summary.triangles_skipped = int(result.skipped);
    summary.triangles_deferred = int(result.deferred);
    summary.inverted_cells = int(result.inverted_cells);
    s.cut_inverted = std::max(s.cut_inverted, result.inverted_cells);
    s.cut_stretched += result.stretched;
    if (result.status == cut::CutStatus::Rejected) {
        summary.status = CutSummary::Status::Rejected;
        summary.rejected_triangle = int(result.rejected_triangle);
        summary.rejected_corner = result.rejected_corner;
        summary.reason = result.reason;
    } else if (!before && result.status == cut::CutStatus::Deferred) {
        summary.status = CutSummary::Status::Deferred; // nothing cut yet, the rest waits
    } else if (before) {
        s.settle_cut(result, summary, *before);
        if (summary.ok()) {
            summary.swept_area = result.swept_area;
            s.swept_area += result.swept_area;
            if (budget > 0)
                s.cut_cells_left -= std::max(Index(result.report.changed_cells.size()),
                    Index(std::ceil(result.report.work)));
        } else {
            s.swept_area_undone += result.swept_area;
        }
    }
    summary.cells_after = int(s.mesh.num_cells());
    summary.cut_ms = watch.ms();
    if (before)
        s.discard(std::move(before));
    return summary;
}

void Simulation::Impl::ensure_cutting() {
    if (cutting)
        return;
    cut::PipelineOptions opt;
    opt.method = scene.cutting.method == scene::CutMethod::Snap ? cut::CutMethod::Snap
                                                                : cut::CutMethod::Split;
    opt.split.snap = scene.cutting.snap_distance;
    opt.split.sliver_volume = scene.cutting.sliver_volume;
    opt.strip_min_advance = opt.method == cut::CutMethod::Split ? blade_min_advance() : 0.0;
    cutting = std::make_unique<cut::CutPipeline>(mesh, initial_mesh, opt);
}

void Simulation::prepare_cutting() {
    Impl& s = *m_impl;
    if (s.cutting && s.cutting_prepared)
        return;
    std::erase_if(s.build_parts, [](const BuildPart& p) { return p.name == "cut"; });
    PartClock clock;
    s.ensure_cutting();
    s.cutting->prepare();
    s.cutting_prepared = true;
    clock.lap(s.build_parts, "cut", true); // build() drops it again with the pipeline
}

void Simulation::Impl::settle_cut(cut::CutResult& result, CutSummary& summary, Snapshot& before) {
    // A cut is all or nothing: if the cutter or the model update fails on some configuration (a
    // cell the basis cannot handle), the mesh and the state go back to what they were and the
    // error is reported; the simulation keeps running on the uncut mesh.
    const cut::CutReport& report = result.report;
    try {
        if (result.status == cut::CutStatus::Failed)
            throw Error("cut", result.reason);
        summary.status = result.status == cut::CutStatus::Deferred ? CutSummary::Status::Deferred
                                                                   : CutSummary::Status::Applied;
        summary.triangles_applied = int(report.triangles - report.triangles_missed);
        summary.cells_split = int(report.new_cells.size());
        summary.nodes_added = int(report.nodes_after - report.nodes_before);
        summary.topology_changed = report.topology_changed;
        if (report.topology_changed) {
            check_model_growth(); // on the cut mesh, before the model follows it
            resize_state_after_cut(report);
            check_cut_cells(report.changed_cells);
            if (scene.integrator.type == integrate::IntegratorKind::Static)
                summary.pieces_fixed = fix_free_pieces();
            else
                summary.fragments_pinned = pin_free_fragments(report.changed_cells);
        }
    } catch (const std::exception& e) {
        restore(before, false);
        summary = CutSummary { .status = CutSummary::Status::Failed,
            .reason = std::string("failed and was undone, the mesh is unchanged: ") + e.what(),
            .triangles_skipped = summary.triangles_skipped,
            .cells_before = summary.cells_before };
        return;
    }
    // Until the next step shows the cut model is sound, the state before the first cut of this
    // tick stays at hand (Simulation::step undoes the cuts when that step fails; the pipeline
    // keeps the mesh of that moment, CutPipeline::undo_all).
    if (summary.topology_changed && !cut_undo) {
        cut_undo = std::make_unique<Snapshot>(std::move(before)); // before's buffers move along
        before.model_mark = 0; // now cut_undo's
    }
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
    return m_impl->blade_min_advance();
}

double Simulation::Impl::blade_min_advance() const {
    if (scene.cutting.method == scene::CutMethod::Snap)
        return 0.0;
    constexpr double kMinAdvance = 0.25; // of the mean cell size
    return kMinAdvance * initial_cell_size;
}

double Simulation::blade_max_advance() const {
    return m_impl->initial_cell_size;
}

CutSummary Simulation::end_stroke() {
    Impl& s = *m_impl;
    CutSummary summary;
    summary.cells_before = summary.cells_after = int(s.mesh.num_cells());
    if (!s.cutting)
        return summary;
    // Face snapping holds faces back while cutting them would pinch an edge; when the blade is
    // lifted they are cut (their pinched edges split), so the stroke ends complete.
    std::unique_ptr<Impl::Snapshot> before;
    cut::CutResult result = s.cutting->end_stroke([&] { before = s.take_snapshot(); });
    if (before)
        s.settle_cut(result, summary, *before);
    if (before)
        s.discard(std::move(before));
    if (summary.status == CutSummary::Status::Failed)
        summary.reason = "finishing the stroke " + summary.reason;
    // The solver's hierarchy was carried over the stroke's cuts: set it up again now that the
    // cut is done (off the tick where the solver can).
    if (s.integrator)
        s.integrator->refresh_preconditioner();
    summary.cells_after = int(s.mesh.num_cells());
    return summary;
}

void Simulation::Impl::check_model_growth() const {
    const double growth = scene.cutting.max_model_growth;
    if (!model || !(growth > 0) || !(initial_element_cost > 0))
        return;
    // A model this small steps in a few milliseconds whatever a cut makes of it (10,400 tets'
    // entries, ~1.5 ms of assembly and ~0.5-2.5 ms per PCG iteration at the rates element_cost
    // was calibrated at): a relative limit would refuse a cut across a coarse mesh for no
    // tick's sake. With 5e5 a single incision through organ_dg's 1,031 tets (as cell-splitting
    // polyhedra) was refused from its 37th sample on (4.07 times the uncut cost; rest
    // completeness 0.83, 0.70 through nodes) while its steps took 1.6-1.8 ms at the p99; let
    // through, 0.99-1.00 with steps of 1.8-3.1 ms at the p99 (decision 0081).
    constexpr double kCostFloor = 1.5e6;
    const double cost = element_cost(mesh);
    if (cost > std::max(growth * initial_element_cost, kCostFloor)) {
        char text[256];
        std::snprintf(text, sizeof text,
            "the cut mesh's steps would cost %.2f x the uncut model's (element matrix entries, "
            "a polyhedron's weighted 4; cutting.max_model_growth = %g): sweeps this dense make "
            "cells that slow every later step",
            cost / initial_element_cost, growth);
        throw Error("cut", text);
    }
}

void Simulation::Impl::resize_state_after_cut(const cut::CutReport& report) {
    if (dg) {
        // DG (dg_part.hpp): a model on the cut mesh, every cell's polynomial carried over.
        dg = dg_after_cut(*dg, scene, mesh, report, state.x, state.v);
        integrator = std::make_unique<integrate::Integrator>(*dg->model, integrator_options(scene));
        node_fixed_mask.assign(3 * mesh.rest.size(), 0);
        scene_forces = VecX::Zero(3 * mesh.num_nodes());
        static_solved = false;
        sync_positions();
        note_embedding_cut(report); // the detailed surface follows the cut, as below
        refresh_topology();
        return;
    }
    const Index n_old = report.nodes_before, n_new = report.nodes_after;
    // Surviving nodes keep their state (renumbered by node_map when the snap cutter compacted
    // nodes); new nodes take displacement and velocity from the material they came from.
    MatX3 x_old = state.x;
    const MatX3 v_old = state.v;
    // Nodes the cutter moved in rest space keep their displacement (the material point moved by
    // the snapping distance, a fraction of a cell; 002 sec. 3.2.2 snaps in the reference
    // configuration for the same reason). Without renumbering (cell splitting) the shift comes
    // first, so that new nodes interpolate the moved positions.
    if (report.node_map.empty())
        for (const auto& [node, old_rest] : report.moved_nodes)
            x_old.row(node) += (mesh.rest[std::size_t(node)] - old_rest).transpose();
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
    // Face snapping renumbers: its moved nodes shift after the copy (ids after the call).
    if (!report.node_map.empty())
        for (const auto& [node, old_rest] : report.moved_nodes)
            state.x.row(node) += (mesh.rest[std::size_t(node)] - old_rest).transpose();
    // Renumbered nodes: a full rebuild. Cells merged away (cell_map) keep the survivors' data.
    // Both leave the model as it was when a cell of the cut mesh cannot be made (MeshError):
    // the undo then needs no rebuild.
    if (!report.node_map.empty())
        model->rebuild_topology(report.node_map); // the solver's hierarchy follows the map
    else
        model->update_cells(report.changed_cells, report.cell_map);
    model->set_fixed_dofs(node_fixed_mask);
    static_solved = false;
    sync_positions();
    note_embedding_cut(report); // embedded.cpp: split the detailed surface where this cut went
    refresh_topology();
}

std::unique_ptr<Simulation::Impl::Snapshot> Simulation::Impl::take_snapshot() {
    std::unique_ptr<Snapshot> snap = spare ? std::move(spare) : std::make_unique<Snapshot>();
    snap->state = state;
    snap->node_fixed_mask = node_fixed_mask;
    snap->scene_forces = scene_forces;
    snap->forces = forces;
    snap->grabs = grabs;
    snap->swept_area = swept_area;
    snap->topology = topology;
    snap->topology_version = topology_version;
    snap->model_mark = model && !dg ? model->mark_undo() : 0;
    return snap; // the mesh: the cut pipeline's undo mirror (CutPipeline::undo)
}

void Simulation::Impl::discard(std::unique_ptr<Snapshot> snap) {
    // Not restorable any more (cut_undo, the tick's first snapshot, is): its model mark goes,
    // the journal after it stays for cut_undo's (at most two marks are held at a time).
    if (model && snap->model_mark != 0)
        model->drop_mark(snap->model_mark);
    spare = std::move(snap); // its buffers serve the next cut's undo copy
}

void Simulation::Impl::restore(const Snapshot& snap, bool published) {
    if (!cutting)
        throw Error("cut", "the mesh before the cut is no longer known");
    // The cutters' adjacency and remembered sweeps refer to the failed edit: the undo forgets
    // them. A published state (a failed step) goes back to before every cut since the last
    // step, a failed cut to before that cut.
    if (published)
        cutting->undo_all();
    else
        cutting->undo();
    state = snap.state;
    node_fixed_mask = snap.node_fixed_mask;
    scene_forces = snap.scene_forces;
    forces = snap.forces;
    grabs = snap.grabs;
    swept_area_undone += swept_area - snap.swept_area; // cuts this undo takes back
    swept_area = snap.swept_area;
    if (dg) {
        dg = make_dg_part(scene, mesh); // the restored mesh's cells, in their old order
        integrator = std::make_unique<integrate::Integrator>(*dg->model, integrator_options(scene));
    } else if (model) {
        // The cells the cuts replaced come back from the model's journal, the appended ones go
        // and the pattern is made again around them: no basis made again, the node ids kept
        // (the AMG hierarchy follows by a remap). Also when the model never followed the cut (it
        // failed before the update): then nothing changes.
        if (!model->revert_to_mark(snap.model_mark))
            model->rebuild_topology();
        model->set_fixed_dofs(node_fixed_mask);
    }
    static_solved = false;
    sync_positions();
    topology = snap.topology;
    topology_version = published ? topology_version + 1 : snap.topology_version;
}

int Simulation::Impl::fix_free_pieces() {
    if (dg)
        return 0; // not for DG yet: a free piece makes a static DG solve fail, undoing the cut
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

int Simulation::Impl::pin_free_fragments(const std::vector<Index>& changed) {
    // Debris: a cut (a re-cut along an earlier one, a blade grazing the skin) can free a few
    // cells from the body. Under gravity with nothing below, such a fragment falls for ever:
    // the live organ re-cut published a single tet 1.6 m below the body. A piece of at most
    // kFragmentCells cells and under kFragmentVolume of the body that reaches no fixed node is
    // held where it is (all its nodes fixed); larger free pieces (a slab cut off) fall under
    // their loads. The search walks the face table from the changed cells and stops at
    // kFragmentCells cells, so its work is bounded by what the cut touched; only a candidate
    // fragment is checked against the whole mesh for a node it shares with the body (hanging
    // by a node or an edge, it is not free).
    if (dg || changed.empty())
        return 0;
    constexpr std::size_t kFragmentCells = 64;
    constexpr double kFragmentVolume = 0.01; // of the body's rest volume
    const Index nc = mesh.num_cells();
    const auto fixed_node = [&](Index n) {
        return node_fixed_mask[3 * std::size_t(n)] || node_fixed_mask[3 * std::size_t(n) + 1]
            || node_fixed_mask[3 * std::size_t(n) + 2];
    };
    // the search that reached each cell; meeting another search's cell means the piece joins
    // one already judged (too big or anchored)
    std::unordered_map<Index, std::size_t> search_of;
    std::vector<Index> piece;
    int pinned = 0;
    for (std::size_t si = 0; si < changed.size(); ++si) {
        const Index start = changed[si];
        if (start < 0 || start >= nc || search_of.count(start))
            continue;
        piece.assign(1, start);
        search_of[start] = si;
        bool free = true;
        for (std::size_t k = 0; k < piece.size() && free; ++k) {
            const mesh::Cell& cell = mesh.cells[std::size_t(piece[k])];
            free = std::none_of(cell.nodes.begin(), cell.nodes.end(), fixed_node);
            for (std::size_t q = 0; q < cell.faces.size() && free; ++q) {
                const mesh::Face& f = mesh.faces[std::size_t(cell.faces[q])];
                const Index other = f.owner == piece[k] ? f.neighbour : f.owner;
                if (other == kNone)
                    continue;
                const auto [it, added] = search_of.emplace(other, si);
                if (!added) {
                    free = it->second == si;
                    continue;
                }
                piece.push_back(other);
            }
            free = free && piece.size() <= kFragmentCells;
        }
        if (!free)
            continue;
        double volume = 0;
        for (Index c : piece)
            volume += mesh.cell_volume(c);
        if (!(volume < kFragmentVolume * body_volume))
            continue;
        // hanging on the body by a node or an edge: not free (the one pass over the mesh, for
        // a candidate only)
        std::vector<Index> nodes;
        for (Index c : piece)
            nodes.insert(nodes.end(), mesh.cells[std::size_t(c)].nodes.begin(),
                mesh.cells[std::size_t(c)].nodes.end());
        std::sort(nodes.begin(), nodes.end());
        nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
        bool hanging = false;
        for (Index c = 0; c < nc && !hanging; ++c) {
            const auto found = search_of.find(c);
            if (found != search_of.end() && found->second == si)
                continue;
            for (Index n : mesh.cells[std::size_t(c)].nodes)
                hanging = hanging || std::binary_search(nodes.begin(), nodes.end(), n);
        }
        if (hanging)
            continue;
        for (Index n : nodes)
            for (std::size_t k = 0; k < 3; ++k)
                node_fixed_mask[3 * std::size_t(n) + k] = 1;
        ++pinned;
    }
    if (pinned > 0)
        model->set_fixed_dofs(node_fixed_mask);
    return pinned;
}

} // namespace polycut::sim
