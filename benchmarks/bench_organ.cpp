// Step time of whole scenes through sim::Simulation (issue 18: organ scale), as a user gets it:
// the scene's own mesh (CGAL-meshed organs included), solver, thread count and node ordering.
//
//   bench_organ SCENE.json... [--steps N] [--warmup W] [--patch JSON]... [--no-error]
//
// Per scene: W warm-up steps from rest (default 10), then N timed steps (default 300). One JSON
// object per scene on stdout:
//   nodes, tets, free_dofs, threads           the model (threads: integrator.threads)
//   build_ms                                   Simulation construction (meshing included) [ms]
//   cpu_ms / wall_ms {median, p99, max}        per step: process CPU time (all threads) and
//                                              wall time [ms]
//   asm_ms, solve_ms {median, p99}             the step report's assembly / solve wall times [ms]
//   its {median, p99, max}                     PCG iterations per step
//   err                                        || x_50 - x_50,ref || / || x_50,ref - X ||, after
//                                              50 steps from rest against the same scene solved
//                                              tightly (PCG + lagged CHOLMOD to 1e-10, cached in
//                                              bench_organ_ref_<name>_<hash>.bin in the working
//                                              directory); the accuracy criterion is 1e-3
//   rolled_back, load                          failed steps; /proc/loadavg (1 min) at the end
//   budget_stops                               timed steps whose solve stopped at
//                                              solver.iteration_budget
// --trace FILE writes one line per step: tick, wall ms, CPU ms, iterations, assembly ms, solve ms.
// --patch applies a JSON merge patch (RFC 7386) to every scene before parsing, e.g.
//   --patch '{"integrator": {"threads": 2}}' or '{"solver": {"tolerance": 0.3}}'.
// Run heavy cases on an idle machine; on a shared one prefer the CPU medians.
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

using namespace polycut;
using json = nlohmann::json;

namespace {

constexpr long kAccuracyStep = 50;

struct Args {
    std::vector<std::string> scenes;
    std::vector<json> patches;
    long steps = 300;
    long warmup = 10;
    bool error = true;
    std::string trace; ///< --trace FILE: one line per step (tick, wall ms, cpu ms, its)
};

json read_json(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw FileError(path, 0, "cannot open");
    return json::parse(in);
}

scene::Scene make_scene(const json& j, const std::string& path) {
    return scene::parse_scene(j.dump(), std::filesystem::path(path).parent_path().string());
}

json stats(std::vector<double> v) {
    if (v.empty())
        return json::object();
    return { { "median", percentile(v, 50) }, { "p99", percentile(v, 99) },
        { "max", *std::max_element(v.begin(), v.end()) } };
}

double load_average() {
    std::ifstream in("/proc/loadavg");
    double l = -1;
    in >> l;
    return l;
}

/// Positions after kAccuracyStep steps from rest of the scene solved tightly, cached on disk by
/// a hash of everything but the solver settings and the thread count.
std::vector<Vec3> reference(const json& scene_json, const std::string& path) {
    json physics = scene_json;
    physics.erase("solver");
    if (physics.contains("integrator"))
        physics["integrator"].erase("threads");
    physics.erase("output");
    physics.erase("description");
    const std::size_t hash = std::hash<std::string> {}(physics.dump());
    char name[128];
    std::snprintf(name, sizeof name, "bench_organ_ref_%s_%016zx.bin",
        scene_json.value("name", "scene").c_str(), hash);
    json tight = scene_json;
    tight["solver"] = { { "type", "pcg" }, { "preconditioner", "lagged_cholesky" },
        { "tolerance", 1e-10 }, { "max_iterations", 5000 }, { "refactor_iterations", 20 },
        { "warm_start", "previous" } };
    if (tight.contains("integrator"))
        tight["integrator"].erase("threads");
    std::vector<Vec3> x;
    std::ifstream in(name, std::ios::binary);
    std::uint64_t n = 0;
    if (in && in.read(reinterpret_cast<char*>(&n), sizeof n)) {
        x.resize(n);
        if (in.read(reinterpret_cast<char*>(x.data()), std::streamsize(sizeof(Vec3) * n)))
            return x;
    }
    sim::Simulation sim(make_scene(tight, path));
    for (long k = 0; k < kAccuracyStep; ++k)
        sim.step();
    x = sim.positions();
    n = x.size();
    std::ofstream out(name, std::ios::binary);
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    out.write(reinterpret_cast<const char*>(x.data()), std::streamsize(sizeof(Vec3) * n));
    return x;
}

double relative_error(
    const std::vector<Vec3>& rest, const std::vector<Vec3>& x, const std::vector<Vec3>& ref) {
    if (x.size() != ref.size() || rest.size() != ref.size())
        return -1;
    double e = 0, u = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        e += (x[i] - ref[i]).squaredNorm();
        u += (ref[i] - rest[i]).squaredNorm();
    }
    return u > 0 ? std::sqrt(e / u) : -1;
}

json run(const std::string& path, const Args& a) {
    json j = read_json(path);
    for (const json& p : a.patches)
        j.merge_patch(p);
    const Stopwatch build;
    sim::Simulation sim(make_scene(j, path));
    const double build_ms = build.ms();
    const std::vector<Vec3> rest = sim.positions();
    std::vector<double> cpu, wall, asm_ms, solve_ms, its;
    long rolled_back = 0;
    long budget_stops = 0;
    double err = -1;
    bool need_error = a.error;
    std::vector<Vec3> x50;
    std::ofstream trace;
    if (!a.trace.empty())
        trace.open(a.trace);
    for (long k = 0; k < a.warmup + a.steps; ++k) {
        const double c0 = process_cpu_ms();
        const Stopwatch sw;
        const sim::StepReport r = sim.step();
        const double w = sw.ms(), c = process_cpu_ms() - c0;
        rolled_back += r.rolled_back ? 1 : 0;
        budget_stops += r.solver_budget_reached ? 1 : 0;
        if (trace)
            trace << r.tick << ' ' << w << ' ' << c << ' ' << r.solver_iterations << ' '
                  << r.assembly_ms << ' ' << r.solve_ms << '\n';
        if (r.tick == kAccuracyStep && need_error)
            x50 = sim.positions();
        if (k < a.warmup)
            continue;
        cpu.push_back(c);
        wall.push_back(w);
        asm_ms.push_back(r.assembly_ms);
        solve_ms.push_back(r.solve_ms);
        its.push_back(r.solver_iterations);
    }
    if (need_error && !x50.empty())
        err = relative_error(rest, x50, reference(j, path));
    const auto stats2 = [](std::vector<double> v) {
        return json { { "median", percentile(v, 50) }, { "p99", percentile(v, 99) } };
    };
    json out;
    out["scene"] = j.value("name", path);
    out["nodes"] = rest.size();
    out["tets"] = sim.cell_count();
    out["threads"] = sim.scene().integrator.threads;
    out["build_ms"] = build_ms;
    out["steps"] = a.steps;
    out["cpu_ms"] = stats(cpu);
    out["wall_ms"] = stats(wall);
    out["asm_ms"] = stats2(asm_ms);
    out["solve_ms"] = stats2(solve_ms);
    out["its"] = stats(its);
    out["err"] = err;
    out["rolled_back"] = rolled_back;
    out["budget_stops"] = budget_stops;
    out["load"] = load_average();
    return out;
}

int usage(const char* why) {
    std::fprintf(stderr,
        "bench_organ: %s\nusage: bench_organ SCENE.json... [--steps N] [--warmup W] "
        "[--patch JSON]... [--no-error] [--trace FILE]\n",
        why);
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string s = argv[i];
        if (s == "--steps" && i + 1 < argc)
            a.steps = std::stol(argv[++i]);
        else if (s == "--warmup" && i + 1 < argc)
            a.warmup = std::stol(argv[++i]);
        else if (s == "--patch" && i + 1 < argc)
            a.patches.push_back(json::parse(argv[++i]));
        else if (s == "--trace" && i + 1 < argc)
            a.trace = argv[++i];
        else if (s == "--no-error")
            a.error = false;
        else if (!s.empty() && s[0] == '-')
            return usage(("unknown option " + s).c_str());
        else
            a.scenes.push_back(s);
    }
    if (a.scenes.empty())
        return usage("no scene");
    try {
        for (const std::string& path : a.scenes)
            std::cout << run(path, a).dump() << std::endl;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_organ: %s\n", e.what());
        return 1;
    }
    return 0;
}
