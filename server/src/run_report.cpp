#include "run_report.hpp"

#include <algorithm>

namespace polycut::run {

nlohmann::json summary_json(const Summary& s) {
    return { { "count", s.count }, { "mean", s.mean }, { "median", s.median }, { "p90", s.p90 },
        { "p99", s.p99 }, { "max", s.max } };
}

namespace {
nlohmann::json mesh_json(const sim::MeshStats& m) {
    return { { "nodes", m.nodes }, { "cells", m.cells },
        { "boundary_triangles", m.boundary_triangles }, { "rest_volume", m.rest_volume },
        { "components", m.components }, { "surface_closed", m.surface_closed } };
}

/// The repair report and tet quality of a CGAL-meshed geometry (docs/scenes.md, geometry).
nlohmann::json meshing_json(const sim::MeshingSummary& m) {
    nlohmann::json j
        = { { "source", m.source }, { "mesh_ms", m.mesh_ms }, { "total_ms", m.total_ms } };
    if (m.has_repair)
        j["repair"] = { { "mode", m.repair_mode }, { "applied", m.repair_applied },
            { "repaired", m.repair_applied != "none" }, { "summary", m.repair_summary },
            { "faces_in", m.faces_in }, { "faces_out", m.faces_out },
            { "holes_filled", m.holes_filled }, { "holes_unfilled", m.holes_unfilled },
            { "self_intersections_in", m.self_intersections_in },
            { "self_intersections_out", m.self_intersections_out },
            { "components_in", m.components_in }, { "components_out", m.components_out },
            { "wrapped", m.wrapped }, { "volume_in", m.volume_in }, { "volume_out", m.volume_out },
            { "volume_change", m.volume_change }, { "time_ms", m.repair_ms } };
    j["quality"] = { { "tets", m.tets }, { "min_dihedral_deg", m.min_dihedral_deg },
        { "max_dihedral_deg", m.max_dihedral_deg },
        { "radius_ratio",
            { { "min", m.radius_ratio_min }, { "p1", m.radius_ratio_p1 },
                { "p50", m.radius_ratio_p50 } } },
        { "slivers", m.slivers }, { "sliver_dihedral_deg", m.sliver_dihedral_deg },
        { "has_slivers", m.has_slivers }, { "summary", m.quality_summary } };
    return j;
}
/// The build report: each part with its cost, the bases by kind, and the first step, which
/// carries the solver's set-up (analysis, factorization or AMG hierarchy at the first solve).
nlohmann::json build_json(const RunRecord& r) {
    nlohmann::json parts = nlohmann::json::array();
    for (const sim::BuildPart& p : r.build.parts)
        parts.push_back({ { "name", p.name }, { "built", p.built }, { "ms", p.ms },
            { "rss_kb", p.rss_kb }, { "detail", p.detail } });
    nlohmann::json j = { { "parts", parts },
        { "bases",
            { { "p1", r.build.p1_bases }, { "q1", r.build.q1_bases },
                { "polyhedral", r.build.polyhedral_bases }, { "dg_cells", r.build.dg_cells } } } };
    if (!r.step_ms.empty()) {
        j["first_step_ms"] = r.step_ms.front();
        std::vector<double> rest(r.step_ms.begin() + 1, r.step_ms.end());
        if (!rest.empty())
            j["later_steps_median_ms"] = summarize(rest).median;
    }
    return j;
}
} // namespace

nlohmann::json to_json(const RunRecord& r) {
    nlohmann::json j;
    j["scene"] = r.scene;
    j["method"] = r.method;
    j["mesh"] = mesh_json(r.before);
    if (r.meshing.meshed)
        j["meshing"] = meshing_json(r.meshing);
    j["steps"] = r.steps;
    nlohmann::json probes = nlohmann::json::object();
    for (const auto& [name, u] : r.probes)
        probes[name] = { { "displacement", { u.x(), u.y(), u.z() } }, { "magnitude", u.norm() } };
    j["probes"] = probes;
    j["timing"] = { { "step_ms", summary_json(summarize(r.step_ms)) },
        { "assembly_ms", summary_json(summarize(r.assembly_ms)) },
        { "solve_ms", summary_json(summarize(r.solve_ms)) } };
    j["cost"] = { { "setup_ms", r.setup_ms }, { "setup_cpu_ms", r.setup_cpu_ms },
        { "step_cpu_ms", summary_json(summarize(r.step_cpu_ms)) },
        { "setup_rss_mb", double(r.setup_rss_kb) / 1024.0 },
        { "peak_rss_mb", double(r.peak_rss_kb) / 1024.0 } };
    j["model"] = { { "dofs", r.model.dofs }, { "free_dofs", r.model.free_dofs },
        { "nonzeros", r.model.nonzeros },
        { "cells",
            { { "tet", r.model.tets }, { "hex", r.model.hexes },
                { "polyhedron", r.model.polyhedra } } } };
    j["build"] = build_json(r);
    if (!r.sample_points.empty()) {
        nlohmann::json u = nlohmann::json::array(), inside = nlohmann::json::array();
        for (std::size_t i = 0; i < r.sample_points.size(); ++i) {
            u.push_back({ r.sample_u[i].x(), r.sample_u[i].y(), r.sample_u[i].z() });
            inside.push_back(r.sample_inside[i] != 0);
        }
        j["samples"]
            = { { "count", r.sample_points.size() }, { "displacement", u }, { "inside", inside } };
    }
    j["solver"] = { { "iterations", summary_json(summarize(r.iterations)) },
        { "max_residual", r.max_residual }, { "rolled_back_steps", r.rolled_back } };
    if (r.has_cuts) {
        const double vb = r.before.rest_volume, va = r.after.rest_volume;
        j["cut"] = { { "triangles", r.cut_triangles }, { "pieces_fixed", r.pieces_fixed },
            { "rest_volume_before", vb }, { "rest_volume_after", va },
            { "rest_volume_relative_change", vb > 0 ? std::abs(va - vb) / vb : 0.0 },
            { "surface_closed", r.after.surface_closed }, { "components", r.after.components },
            { "max_cut_ms",
                r.cut_ms.empty() ? 0.0 : *std::max_element(r.cut_ms.begin(), r.cut_ms.end()) },
            { "cut_ms", summary_json(summarize(r.cut_ms)) }, { "cut_area", r.after.cut_area },
            { "swept_area", r.after.swept_area },
            { "swept_area_undone", r.after.swept_area_undone },
            { "completeness", r.after.completeness() }, { "failed_cuts", r.failed_cuts },
            { "undone_cuts", r.undone_cuts } };
        j["mesh_after"] = mesh_json(r.after);
    }
    if (!r.bodies.empty()) {
        nlohmann::json bodies = nlohmann::json::array();
        for (const auto& b : r.bodies)
            bodies.push_back({ { "kind", b.kind }, { "id", b.id }, { "name", b.name },
                { "max_force", { b.max_force.x(), b.max_force.y(), b.max_force.z() } },
                { "max_force_tick", b.max_force_tick }, { "max_depth", b.max_depth },
                { "final_force", { b.final_force.x(), b.final_force.y(), b.final_force.z() } } });
        j["contact"] = { { "contact_ms", summary_json(summarize(r.contact_ms)) },
            { "points", summary_json(summarize(r.contact_points)) }, { "bodies", bodies } };
    }
    // Distinct warnings, in order of first appearance.
    std::vector<std::string> distinct;
    for (const auto& w : r.warnings)
        if (std::find(distinct.begin(), distinct.end(), w) == distinct.end())
            distinct.push_back(w);
    j["warnings"] = distinct;
    return j;
}

void RunRecord::add_contact(const std::vector<sim::BodyReaction>& reactions, double ms, long tick) {
    if (reactions.empty())
        return;
    contact_ms.push_back(ms);
    double points = 0;
    for (const sim::BodyReaction& r : reactions) {
        points += r.points;
        auto it = std::find_if(bodies.begin(), bodies.end(),
            [&](const BodyPeak& b) { return b.kind == r.kind && b.id == r.id; });
        if (it == bodies.end()) {
            bodies.push_back(BodyPeak { r.kind, r.name, r.id, {}, 0, 0, {} });
            it = bodies.end() - 1;
        }
        if (r.force.norm() > it->max_force.norm()) {
            it->max_force = r.force;
            it->max_force_tick = tick;
        }
        it->max_depth = std::max(it->max_depth, r.max_depth);
        it->final_force = r.force;
    }
    contact_points.push_back(points);
}

} // namespace polycut::run
