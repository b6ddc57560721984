// Cost of cutting while the simulation runs (issue 12 item 5), in process, as the server spends
// it at each tick of a scalpel stroke: the cut of the tick's sweep (two triangles per sample,
// samples held until the blade moved Simulation::blade_min_advance(), as the server does) and the
// step after it. No network, no other client: the figures the live runs (polycut_incision.py)
// add scheduling noise to.
//
//   bench_cut SCENE.json... [--cutter snap|split|asis] [--ticks N] [--settle S] [--depth D]
//             [--strokes K] [--offset Y] [--after A] [--explode-every E]
//
// The stroke: a blade from 2 cm above the tissue's top down to D x its height (default 0.4),
// in the plane y = centre + Y (default 2.5 mm: between grid planes on the shipped boxes), moving
// along x over the middle 60 % of the tissue in N ticks (default 180 = 3 s at 60 Hz), after S steps
// of settling (default 10); with K > 1 the same stroke (in world space) K times, a re-cut of the
// deformed body (default 1); then A ticks of stepping without a cut (default 0): the hand-over
// of the set-up the end of the stroke asks for. With --explode-every E, every E-th tick of a stroke
// whose cut changed the mesh grabs the blade's tip with a 1e9 N/m spring dragged 1 m, so that
// its step explodes and undoes the tick's cuts (decision 0070: the model goes back from its
// journal). One JSON object per scene on stdout:
//   nodes, cells (before/after), cutter, model_growth (MeshStats::model_growth)
//   cut_ms, step_ms, tick_ms {median, p99, max}   per tick wall times [ms] (tick = cut + step)
//   cut_cpu_ms, tick_cpu_ms                        the same in CPU time of the process (all
//                                                  threads): what the work costs, whatever else
//                                                  the shared machine runs
//   solve_ms, its {median, p99, max}               the step's linear solves [ms], PCG iterations
//   ticks_over_16_7, ticks_over_50                 ticks above the 60 Hz budget / the 50 ms bound
//   completeness, failed_cuts, undone               cut area / 2 x swept area; failures
//   undo_reasons                                   the reasons of the first failed or undone cuts
//   after {tick_ms, its}                           with --after: the ticks after the strokes
//   explode {undone, tick_ms, next_step_ms}         with --explode-every: undone cuts, the ticks
//                                                  that undid them (cut, failed step, undo) and
//                                                  the step of the tick after each
// With BENCH_CUT_TRACE=1 in the environment, one line per tick on stderr (wall ms of the tick, its
// cut, assembly and solves; CPU ms; cells; PCG iterations).
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

using namespace polycut;
using json = nlohmann::json;

namespace {

struct Args {
    std::vector<std::string> scenes;
    std::string cutter = "asis";
    int ticks = 180;
    int settle = 10;
    double depth = 0.4;
    int strokes = 1; // the same stroke again, in world space, after the first (a re-cut)
    double offset = 0.0025; // the blade's plane: y = centre + offset [m]
    int after = 0; // ticks stepped after the last stroke
    int explode_every = 0; // every E-th tick of a stroke that cuts, a grab makes its step explode
};

/// CPU time of the process, all threads [ms].
double cpu_ms() {
    timespec t {};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

json percentiles(std::vector<double> v) {
    if (v.empty())
        return json::object();
    std::sort(v.begin(), v.end());
    auto at
        = [&](double q) { return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))]; };
    return { { "median", at(0.5) }, { "p99", at(0.99) }, { "max", v.back() } };
}

json run(const std::string& path, const Args& a) {
    std::ifstream in(path);
    if (!in)
        throw FileError(path, 0, "cannot open");
    json j = json::parse(in);
    if (a.cutter == "snap") {
        j["method"] = "tet";
        j["cutting"] = { { "method", "snap" } };
    } else if (a.cutter == "split") {
        j["method"] = "mvc";
        j["cutting"] = { { "method", "split" } };
    }
    scene::Scene sc
        = scene::parse_scene(j.dump(), std::filesystem::path(path).parent_path().string());
    sim::Simulation s(std::move(sc));
    s.prepare_cutting(); // as the server does when it builds a scene, off the loop
    for (int k = 0; k < a.settle; ++k)
        s.step();
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Vec3& p : s.positions()) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Vec3 c = 0.5 * (lo + hi), size = hi - lo;
    const double top = hi.z() + 0.02, bottom = hi.z() - a.depth * size.z();
    const double y = c.y() + a.offset;
    auto blade = [&](int k) {
        const double x = lo.x() + size.x() * (0.2 + 0.6 * double(k) / double(a.ticks - 1));
        return std::pair<Vec3, Vec3> { Vec3(x, y, top), Vec3(x, y, bottom) };
    };
    std::vector<double> cut_ms, step_ms, tick_ms, its, solve_ms, cut_cpu, tick_cpu;
    int failed = 0, undone = 0, over_budget = 0, over_50 = 0;
    std::vector<std::string> reasons; // the first few undone cuts' warnings
    const long cells_before = s.cell_count();
    auto last = blade(0);
    bool held = false;
    std::vector<Vec3> before = s.positions(); // for the trace
    // Triangles past a tick's cut budget wait for the next tick, as the server carries them.
    std::vector<std::array<Vec3, 3>> waiting;
    int deferred = 0;
    // --explode-every: the ticks whose step explodes, and the step of the tick after each
    std::vector<double> explode_tick_ms, after_undo_ms;
    int exploded = 0;
    bool next_step = false;
    std::uint64_t topology_seen = s.topology_version();
    auto cut_now = [&](std::vector<std::array<Vec3, 3>> tris) {
        tris.insert(tris.begin(), waiting.begin(), waiting.end());
        waiting.clear();
        if (tris.empty())
            return;
        const sim::CutSummary done = s.cut(tris);
        failed += done.ok() ? 0 : 1;
        if (!done.ok() && reasons.size() < 5)
            reasons.push_back("cut: " + done.reason);
        waiting.assign(tris.end() - done.triangles_deferred, tris.end());
        deferred += done.triangles_deferred;
    };
    auto sweep = [&](const std::pair<Vec3, Vec3>& q) {
        cut_now({ { last.first, last.second, q.first }, { last.second, q.second, q.first } });
        last = q;
        held = false;
    };
    for (int t = 1; t <= a.ticks * a.strokes; ++t) {
        const int k = (t - 1) % a.ticks + 1;
        if (k == 1 && t > 1) { // the next stroke starts where the first did
            last = blade(0);
            held = false;
        }
        Stopwatch tick;
        const double cpu0 = cpu_ms();
        if (k < a.ticks) {
            const auto q = blade(k);
            const double advance
                = std::max((q.first - last.first).norm(), (q.second - last.second).norm());
            if (advance < s.blade_min_advance()) {
                held = true;
                cut_now({});
            } else {
                sweep(q);
            }
        } else {
            if (held)
                sweep(blade(a.ticks - 1));
            else
                cut_now({});
            if (waiting.empty()) {
                const sim::CutSummary done = s.end_stroke();
                failed += done.ok() ? 0 : 1;
                if (!done.ok() && reasons.size() < 5)
                    reasons.push_back("end_stroke: " + done.reason);
            }
        }
        const double cut = tick.ms(), cpu_cut = cpu_ms() - cpu0;
        const bool explode = a.explode_every > 0 && k % a.explode_every == 0
            && s.topology_version() != topology_seen;
        if (explode) {
            // a 1e9 N/m grab at the blade's tip dragged 1 m: the step after the cut explodes, is
            // rolled back and undoes the tick's cuts (the grab, made after them, goes too)
            sim::GrabSpec g;
            g.point = last.second;
            g.stiffness = 1e9;
            try {
                s.move_grab(s.grab(g), last.second + Vec3(1.0, 0, 0));
            } catch (const Error&) {
                // the tip outside the material: this tick steps as usual
            }
        }
        const sim::StepReport r = s.step();
        if (explode) {
            explode_tick_ms.push_back(tick.ms());
            exploded += r.cut_undone ? 1 : 0;
            next_step = true;
        } else if (next_step) {
            after_undo_ms.push_back(tick.ms() - cut);
            next_step = false;
        }
        topology_seen = s.topology_version();
        const double total = tick.ms();
        cut_cpu.push_back(cpu_cut);
        if (std::getenv("BENCH_CUT_TRACE")) {
            // How far the body reaches from its centre and how far a node moved in the step
            // [m]: a slowly growing instability shows here long before any guard trips.
            double reach = 0, moved = 0;
            const auto& p = s.positions();
            for (std::size_t i = 0; i < p.size(); ++i) {
                reach = std::max(reach, (p[i] - c).norm());
                if (i < before.size())
                    moved = std::max(moved, (p[i] - before[i]).norm());
            }
            before = p;
            std::fprintf(stderr,
                "tick %d wall %.1f cut %.1f asm %.1f solve %.1f cut_cpu %.1f tick_cpu %.1f cells "
                "%ld its %d "
                "reach %.4g moved %.3g%s\n",
                t, tick.ms(), cut, r.assembly_ms, r.solve_ms, cpu_cut, cpu_ms() - cpu0,
                long(s.cell_count()), r.solver_iterations, reach, moved,
                r.cut_undone        ? " undone"
                    : r.rolled_back ? " rolled back"
                                    : "");
            for (const std::string& w : r.warnings)
                std::fprintf(stderr, "  %s\n", w.c_str());
        }
        tick_cpu.push_back(cpu_ms() - cpu0);
        undone += r.cut_undone ? 1 : 0;
        if (r.cut_undone && reasons.size() < 3 && !r.warnings.empty())
            reasons.push_back(r.warnings.front());
        cut_ms.push_back(cut);
        its.push_back(double(r.solver_iterations));
        solve_ms.push_back(r.solve_ms);
        step_ms.push_back(total - cut);
        tick_ms.push_back(total);
        over_budget += total > 1000.0 / 60.0 ? 1 : 0;
        over_50 += total > 50 ? 1 : 0;
    }
    if (!waiting.empty()) { // the budget's rest, untimed
        while (!waiting.empty()) {
            s.step();
            cut_now({});
        }
        failed += s.end_stroke().ok() ? 0 : 1;
        undone += s.step().cut_undone ? 1 : 0;
    }
    std::vector<double> after_ms, after_its;
    for (int k = 1; k <= a.after; ++k) {
        Stopwatch tick;
        const sim::StepReport r = s.step();
        after_ms.push_back(tick.ms());
        after_its.push_back(double(r.solver_iterations));
        undone += r.cut_undone ? 1 : 0;
        if (std::getenv("BENCH_CUT_TRACE"))
            std::fprintf(stderr, "after %d wall %.1f asm %.1f solve %.1f its %d\n", k,
                after_ms.back(), r.assembly_ms, r.solve_ms, r.solver_iterations);
    }
    const sim::MeshStats st = s.mesh_stats();
    const sim::ModelStats ms = s.model_stats();
    return { { "scene", path }, { "cutter", a.cutter }, { "nodes", s.positions().size() },
        { "free_dofs", ms.free_dofs }, { "nonzeros", ms.nonzeros },
        { "model_growth", st.model_growth }, { "cells_before", cells_before },
        { "cells_after", s.cell_count() }, { "ticks", a.ticks * a.strokes },
        { "cut_ms", percentiles(cut_ms) }, { "step_ms", percentiles(step_ms) },
        { "solve_ms", percentiles(solve_ms) }, { "its", percentiles(its) },
        { "tick_ms", percentiles(tick_ms) }, { "cut_cpu_ms", percentiles(cut_cpu) },
        { "tick_cpu_ms", percentiles(tick_cpu) }, { "ticks_over_16_7", over_budget },
        { "ticks_over_50", over_50 }, { "completeness", st.completeness() },
        { "failed_cuts", failed }, { "deferred_triangles", deferred }, { "undone", undone },
        { "undo_reasons", reasons },
        { "explode",
            a.explode_every > 0
                ? json { { "undone", exploded }, { "tick_ms", percentiles(explode_tick_ms) },
                    { "next_step_ms", percentiles(after_undo_ms) } }
                : json() },
        { "after",
            a.after > 0
                ? json { { "tick_ms", percentiles(after_ms) }, { "its", percentiles(after_its) } }
                : json() } };
}

} // namespace

int main(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc)
                throw InputError(arg, "needs a value");
            return argv[++i];
        };
        if (arg == "--cutter")
            a.cutter = value();
        else if (arg == "--ticks")
            a.ticks = std::stoi(value());
        else if (arg == "--settle")
            a.settle = std::stoi(value());
        else if (arg == "--depth")
            a.depth = std::stod(value());
        else if (arg == "--offset")
            a.offset = std::stod(value());
        else if (arg == "--strokes")
            a.strokes = std::stoi(value());
        else if (arg == "--explode-every")
            a.explode_every = std::stoi(value());
        else if (arg == "--after")
            a.after = std::stoi(value());
        else
            a.scenes.push_back(arg);
    }
    if (a.scenes.empty() || a.ticks < 2) {
        std::cerr << "usage: bench_cut SCENE.json... [--cutter snap|split|asis] [--ticks N >= 2] "
                     "[--settle S] [--depth D] [--strokes K] [--offset Y] [--after A]\n";
        return 2;
    }
    try {
        for (const std::string& path : a.scenes)
            std::cout << run(path, a).dump() << std::endl;
    } catch (const std::exception& e) {
        std::cerr << "bench_cut: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
