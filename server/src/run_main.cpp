// polycut-run: runs a scene without a server and prints one JSON document to stdout.
//   polycut-run SCENE.json [--steps N] [--vtu DIR] [--samples POINTS.json]
// Static scenes are solved to convergence; dynamic scenes run N steps (default: the scene's
// output.steps). Scripted sweeps in the scene are applied at their ticks. CGAL-meshed geometry
// adds "meshing" (repair and tet quality) to the report. The report's "cost" holds set-up time,
// CPU time per step and peak memory, "model" the DOFs and nonzeros; --samples reads
// {"points": [[x, y, z], ...]} (rest space [m]) and reports the displacement there at the end
// (a trade study's field comparison, docs/study.md). Bad input: a message on stderr and exit
// status 2.
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/mesh/io_pvd.hpp"
#include "polycut/sim/simulation.hpp"
#include "run_report.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <sys/resource.h>

namespace {

int usage(const char* why) {
    std::fprintf(stderr,
        "polycut-run: %s\nusage: polycut-run SCENE.json [--steps N] [--vtu DIR] "
        "[--samples POINTS.json]\n",
        why);
    return 2;
}

/// Peak resident set size of this process so far [KiB].
long peak_rss_kb() {
    rusage u {};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

/// Reads {"points": [[x, y, z], ...]}; throws polycut::InputError naming the bad entry.
std::vector<polycut::Vec3> read_points(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw polycut::FileError(path, 0, "cannot open the samples file");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("points") || !j["points"].is_array())
        throw polycut::InputError(path, "expected {\"points\": [[x, y, z], ...]}");
    std::vector<polycut::Vec3> out;
    for (std::size_t i = 0; i < j["points"].size(); ++i) {
        const auto& p = j["points"][i];
        if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number()
            || !p[2].is_number())
            throw polycut::InputError(
                path + ": /points/" + std::to_string(i), "must be [x, y, z] [m]");
        out.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
        if (!out.back().allFinite())
            throw polycut::InputError(path + ": /points/" + std::to_string(i), "must be finite");
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    using namespace polycut;
    std::string scene_path, vtu_dir, samples_path;
    long steps = -1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--steps" && i + 1 < argc) {
            char* end = nullptr;
            steps = std::strtol(argv[++i], &end, 10);
            if (!end || *end != '\0' || steps < 0)
                return usage("--steps needs a non-negative integer");
        } else if (a == "--vtu" && i + 1 < argc) {
            vtu_dir = argv[++i];
        } else if (a == "--samples" && i + 1 < argc) {
            samples_path = argv[++i];
        } else if (a == "--help" || a == "-h") {
            usage("help");
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            return usage(("unknown option " + a).c_str());
        } else if (scene_path.empty()) {
            scene_path = a;
        } else {
            return usage("only one scene file");
        }
    }
    if (scene_path.empty())
        return usage("no scene file given");

    try {
        const std::vector<Vec3> sample_points
            = samples_path.empty() ? std::vector<Vec3> {} : read_points(samples_path);
        scene::Scene scene = scene::load_scene(scene_path);
        // Errors found while building the mesh and model name the file like parse errors do.
        auto make_sim = [&] {
            try {
                return std::make_unique<sim::Simulation>(std::move(scene));
            } catch (const SceneError& e) {
                throw SceneError(e.where(), e.problem() + " (in " + scene_path + ")");
            }
        };
        const Stopwatch setup_watch;
        const double setup_cpu0 = process_cpu_ms();
        const std::unique_ptr<sim::Simulation> sim_ptr = make_sim();
        sim::Simulation& sim = *sim_ptr;
        const scene::Scene& sc = sim.scene();
        run::RunRecord rec;
        rec.setup_ms = setup_watch.ms();
        rec.setup_cpu_ms = process_cpu_ms() - setup_cpu0;
        rec.setup_rss_kb = peak_rss_kb();
        rec.scene = sc.name;
        rec.method = scene::to_string(sc.method);
        rec.meshing = sim.meshing_summary();
        if (rec.meshing.has_slivers)
            rec.warnings.push_back("meshing: " + std::to_string(rec.meshing.slivers)
                + " slivers (tets with a dihedral angle under "
                + std::to_string(int(rec.meshing.sliver_dihedral_deg))
                + " deg): use a smaller cell_size, or optimize with perturb and exude");
        rec.before = sim.mesh_stats();
        if (steps < 0)
            steps = sim.is_static() ? 1 : sc.output.steps;
        if (!vtu_dir.empty())
            std::filesystem::create_directories(vtu_dir);
        // ParaView opens DIR/series.pvd: every written step with its simulated time [s].
        mesh::PvdCollection series(vtu_dir + "/series.pvd");
        auto write_frame = [&](long tick) {
            if (vtu_dir.empty())
                return;
            char name[64];
            std::snprintf(name, sizeof name, "frame_%06ld.vtu", tick);
            sim.write_vtu(vtu_dir + "/" + name);
            series.add(sim.time(), name);
        };
        write_frame(0);
        // Sweeps whose tick is past the last step are applied at the end.
        std::size_t next_sweep = 0;
        auto sweeps = sc.cutting.sweeps;
        std::stable_sort(sweeps.begin(), sweeps.end(),
            [](const auto& a, const auto& b) { return a.tick < b.tick; });
        for (long s = 0; s < steps || next_sweep < sweeps.size(); ++s) {
            while (next_sweep < sweeps.size()
                && (sweeps[next_sweep].tick <= sim.tick() || s >= steps)) {
                rec.has_cuts = true;
                rec.cut_triangles += long(sweeps[next_sweep].triangles.size());
                auto& triangles = sweeps[next_sweep].triangles;
                const auto cut = sim.cut(triangles);
                rec.cut_ms.push_back(cut.cut_ms);
                rec.pieces_fixed += cut.pieces_fixed;
                if (cut.status == sim::CutSummary::Status::Rejected) {
                    // A bad sweep in the scene file.
                    throw polycut::SceneError("/cutting/sweeps/" + std::to_string(next_sweep)
                            + "/triangles/" + std::to_string(cut.rejected_triangle),
                        cut.reason);
                }
                if (cut.status == sim::CutSummary::Status::Failed) {
                    // The cut was undone; the run goes on as the server would, and says so.
                    ++rec.failed_cuts;
                    rec.warnings.push_back(cut.reason);
                }
                if (cut.triangles_deferred > 0) {
                    // Past the tick's cut budget: the rest is cut after the next step.
                    triangles.erase(triangles.begin(), triangles.end() - cut.triangles_deferred);
                    break;
                }
                ++next_sweep;
            }
            if (s >= steps && next_sweep >= sweeps.size())
                break;
            // (past the last step only while the cut budget defers sweep triangles)
            const double cpu0 = process_cpu_ms();
            const sim::StepReport r = sim.step();
            rec.step_cpu_ms.push_back(process_cpu_ms() - cpu0);
            rec.steps++;
            rec.step_ms.push_back(r.step_ms);
            rec.assembly_ms.push_back(r.assembly_ms);
            rec.solve_ms.push_back(r.solve_ms);
            rec.iterations.push_back(double(r.solver_iterations));
            rec.add_contact(sim.contact_reactions(), sim.contact_ms(), sim.tick());
            rec.max_residual = std::max(rec.max_residual, r.residual);
            rec.rolled_back += r.rolled_back ? 1 : 0;
            rec.undone_cuts += r.cut_undone ? 1 : 0;
            rec.warnings.insert(rec.warnings.end(), r.warnings.begin(), r.warnings.end());
            if (sim.tick() % sc.output.vtu_every == 0 || s + 1 == steps)
                write_frame(sim.tick());
        }
        rec.after = sim.mesh_stats();
        if (!rec.has_cuts && !sc.cutting.sweeps.empty())
            rec.has_cuts = true;
        for (const auto& p : sc.probes)
            rec.probes.emplace_back(p.name, sim.probe_displacement(p.name));
        rec.model = sim.model_stats();
        rec.build = sim.build_report(); // at the end: lazy parts say whether the run needed them
        if (!sample_points.empty()) {
            rec.sample_points = sample_points;
            sim.sample_displacements(sample_points, rec.sample_u, rec.sample_inside);
        }
        rec.peak_rss_kb = peak_rss_kb();
        std::cout << run::to_json(rec).dump(2) << std::endl;
        return 0;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-run: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-run: internal error: %s\n", e.what());
        return 3;
    }
}
