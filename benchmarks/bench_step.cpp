// Corotated implicit Euler step on the Kuhn tet boxes of issue 3 item 6
// (assets/scenes/bench_box*.json, built here programmatically the same way): a 0.1 m cube of n^3
// blocks x 6 Kuhn tets, x = 0 fixed, gravity, E = 10 kPa, nu = 0.45, rho = 1000, beta = 0.01, dt =
// 0.01.
//
//   Step/box<n>/<method>/tol<t>: 10 warm-up steps from rest, then 50 timed steps. Counters:
//     med_ms, p99_ms   process CPU time per step (all threads: a background factorization counts)
//     wall_med_ms      wall time per step (pessimistic on a loaded machine)
//     its              median PCG iterations per step
//     asm_ms, slv_ms   median of the step report's assembly / solve wall times
//     err              || x_50 - x_50,ref || / || x_50,ref - X || after 50 steps from rest, with
//     the
//                      reference from a tightly converged run (PCG + lagged CHOLMOD to 1e-12,
//                      cached in bench_step_ref_<n>.bin in the working directory)
//   Assemble/box<n>, SpMV/box<n>, PcgIteration/box<n>/<kind>, AmgSetup/box<n>: the parts of a
//   step, at the state after 20 steps. "_hc" (amg20_hc, PcgIteration amg_hc): hypre's own
//   V-cycle instead of the fused one (AmgOptions::fused_cycle = false).
//
// Run one thread: OPENBLAS_NUM_THREADS=1 ./bench_step --benchmark_filter=box20
// POLYCUT_BENCH_AMG overrides solve::AmgOptions of every AMG configuration, for tuning: a comma
// list of key=value with keys theta, agg, pmax, coarse, sweeps, smoother (gs, jacobi, cheby),
// cf (0/1), rbm (0/1), rbm_pmax, fused (0/1); e.g. POLYCUT_BENCH_AMG=rbm=1,smoother=jacobi.
// Google Benchmark's CPU column is the process CPU time; on the shared machine prefer it to wall.
#include "polycut/common/stats.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/solve/cholmod_solver.hpp"
#include "polycut/solve/pcg.hpp"

#include <Eigen/Cholesky>
#include <benchmark/benchmark.h>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace polycut;
using namespace polycut::integrate;

namespace {

constexpr int kWarmup = 10;
constexpr int kTimed = 50;
constexpr int kAccuracyStep = 50;

/// One benchmark box: the mesh and a model over it (both on the heap: the model points at the
/// mesh).
struct Box {
    std::unique_ptr<mesh::Mesh> mesh;
    std::unique_ptr<elasticity::ElasticModel> model;
};

elasticity::Material box_material() {
    elasticity::Material m;
    m.youngs_modulus = 1e4;
    m.poisson_ratio = 0.45;
    m.density = 1000;
    m.rayleigh_stiffness = 0.01;
    return m;
}

Box make_box(int n) {
    Box b;
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    b.mesh = std::make_unique<mesh::Mesh>(mesh::tet_grid(g, mesh::TetSplit::Kuhn6));
    std::vector<std::uint8_t> fixed(std::size_t(b.mesh->num_nodes()), 0);
    for (Index i = 0; i < b.mesh->num_nodes(); ++i)
        fixed[std::size_t(i)] = std::abs(b.mesh->rest[std::size_t(i)].x()) < 1e-9;
    b.model = std::make_unique<elasticity::ElasticModel>(
        *b.mesh, box_material(), basis::BasisOptions {}, elasticity::fix_nodes(fixed));
    return b;
}

IntegratorOptions step_options(const SolverOptions& solver) {
    IntegratorOptions o;
    o.kind = IntegratorKind::ImplicitEuler;
    o.dt = 0.01;
    o.force_mode = elasticity::ForceMode::Corotated;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver = solver;
    return o;
}

/// AmgOptions with the overrides of POLYCUT_BENCH_AMG (see the file comment).
solve::AmgOptions amg_options() {
    solve::AmgOptions o;
    const char* env = std::getenv("POLYCUT_BENCH_AMG");
    std::stringstream list(env ? env : "");
    std::string item;
    while (std::getline(list, item, ',')) {
        const auto eq = item.find('=');
        if (eq == std::string::npos)
            continue;
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        if (key == "theta")
            o.strong_threshold = std::stod(value);
        else if (key == "agg")
            o.aggressive_levels = std::stoi(value);
        else if (key == "pmax")
            o.interpolation_max_elements = std::stoi(value);
        else if (key == "coarse")
            o.max_coarse_size = std::stoi(value);
        else if (key == "sweeps")
            o.sweeps = std::stoi(value);
        else if (key == "smoother")
            o.smoother = value == "jacobi" ? solve::AmgSmoother::L1Jacobi
                : value == "cheby"         ? solve::AmgSmoother::Chebyshev
                                           : solve::AmgSmoother::GaussSeidel;
        else if (key == "cf")
            o.cf_order = std::stoi(value) != 0;
        else if (key == "rbm")
            o.rigid_body_modes = std::stoi(value) != 0;
        else if (key == "fused")
            o.fused_cycle = std::stoi(value) != 0;
        else if (key == "rbm_pmax")
            o.rigid_body_max_elements = std::stoi(value);
    }
    return o;
}

/// Coordinates of the free DOFs' nodes at positions x (for rigid-body-mode AMG).
VecX free_coordinates(const elasticity::ElasticModel& model, const MatX3& x) {
    VecX c;
    model.reduce(VecX(flat(x)), c);
    return c;
}

/// A solver configuration of the step benchmark.
struct Method {
    std::string name;
    SolverOptions options;
};

std::vector<Method> methods(double tol) {
    std::vector<Method> list;
    auto add = [&](std::string name, LinearSolverKind kind) {
        SolverOptions s;
        s.kind = kind;
        s.relative_tolerance = tol;
        s.max_iterations = 5000;
        s.amg = amg_options();
        list.push_back({ std::move(name), s });
        return &list.back().options;
    };
    add("jacobi", LinearSolverKind::PcgJacobi);
    add("block_jacobi", LinearSolverKind::PcgBlockJacobi);
    add("lagged", LinearSolverKind::PcgLagged);
    add("ic", LinearSolverKind::PcgIncompleteCholesky)->refactor_every = 10;
    // AMG set-up lagged like the CHOLMOD factor: redone when a solve needs more than 10
    // iterations, or every 20 steps (amg20) whatever the count
    add("amg", LinearSolverKind::PcgAmg)->refactor_iterations = 10;
    SolverOptions* every = add("amg20", LinearSolverKind::PcgAmg);
    every->refactor_every = 20;
    every->refactor_iterations = 1000;
    // amg20 with hypre's own V-cycle instead of the fused one (session 2's configuration)
    SolverOptions* hypre_cycle = add("amg20_hc", LinearSolverKind::PcgAmg);
    hypre_cycle->refactor_every = 20;
    hypre_cycle->refactor_iterations = 1000;
    hypre_cycle->amg.fused_cycle = false;
    return list;
}

/// Displacement after kAccuracyStep steps from rest of a tightly converged run, cached on disk.
const MatX3& reference(int n) {
    static std::map<int, MatX3> cache;
    if (auto it = cache.find(n); it != cache.end())
        return it->second;
    const std::string path = "bench_step_ref_" + std::to_string(n) + ".bin";
    Box b = make_box(n);
    MatX3 x(b.model->num_nodes(), 3);
    std::ifstream in(path, std::ios::binary);
    if (in
        && in.read(reinterpret_cast<char*>(x.data()),
            std::streamsize(sizeof(double) * std::size_t(x.size()))))
        return cache[n] = x;
    SolverOptions s;
    s.kind = LinearSolverKind::PcgLagged;
    s.relative_tolerance = 1e-12;
    s.max_iterations = 5000;
    s.refactor_iterations = 20;
    Integrator integ(*b.model, step_options(s));
    State st = integ.rest_state();
    for (int k = 0; k < kAccuracyStep; ++k)
        integ.step(st);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(st.x.data()),
        std::streamsize(sizeof(double) * std::size_t(st.x.size())));
    return cache[n] = st.x;
}

double relative_error(const Box& b, const MatX3& x, const MatX3& ref) {
    MatX3 u_ref = ref;
    for (Index i = 0; i < u_ref.rows(); ++i)
        u_ref.row(i) -= b.mesh->rest[std::size_t(i)].transpose();
    return (x - ref).norm() / u_ref.norm();
}

void run_steps(benchmark::State& state, int n, SolverOptions solver, bool extrapolate) {
    Box b = make_box(n);
    const MatX3& ref = reference(n);
    IntegratorOptions options = step_options(solver);
    options.extrapolate_warm_start = extrapolate;
    Integrator integ(*b.model, options);
    State st = integ.rest_state();
    int steps = 0;
    double err = -1;
    std::vector<double> cpu, wall, its, asm_ms, slv_ms;
    for (; steps < kWarmup; ++steps)
        integ.step(st);
    bool failed = false;
    for (auto _ : state) {
        const double c0 = process_cpu_ms();
        const StepReport r = integ.step(st);
        cpu.push_back(process_cpu_ms() - c0);
        ++steps;
        wall.push_back(r.step_ms);
        its.push_back(r.solver_iterations);
        asm_ms.push_back(r.assembly_ms);
        slv_ms.push_back(r.solve_ms);
        failed |= r.rolled_back || r.status != solve::SolveStatus::Ok;
        if (steps == kAccuracyStep) {
            state.PauseTiming();
            err = relative_error(b, st.x, ref);
            state.ResumeTiming();
        }
    }
    if (failed)
        state.SkipWithError("a step failed or rolled back");
    state.counters["med_ms"] = percentile(cpu, 50);
    state.counters["p99_ms"] = percentile(cpu, 99);
    state.counters["wall_med_ms"] = percentile(wall, 50);
    state.counters["its"] = percentile(its, 50);
    state.counters["asm_ms"] = percentile(asm_ms, 50);
    state.counters["slv_ms"] = percentile(slv_ms, 50);
    state.counters["err"] = err;
    state.counters["dofs"] = double(b.model->num_free_dofs());
}

/// The state after 20 steps (for the part benchmarks), and the step matrix A there.
struct Snapshot {
    Box box;
    State state;
    solve::SparseMatrix K, A;
    VecX b;
};

const Snapshot& snapshot(int n) {
    static std::map<int, std::unique_ptr<Snapshot>> cache;
    auto& slot = cache[n];
    if (slot)
        return *slot;
    slot = std::make_unique<Snapshot>();
    Snapshot& s = *slot;
    s.box = make_box(n);
    SolverOptions so;
    so.kind = LinearSolverKind::PcgBlockJacobi;
    so.relative_tolerance = 1e-8;
    so.max_iterations = 5000;
    Integrator integ(*s.box.model, step_options(so));
    s.state = integ.rest_state();
    for (int k = 0; k < 20; ++k)
        integ.step(s.state);
    auto& model = *s.box.model;
    s.K = model.make_matrix();
    VecX f;
    model.assemble(s.state.x, elasticity::ForceMode::Corotated, &s.K, &f);
    const double h = 0.01, beta = model.material().rayleigh_stiffness;
    s.A = (h * beta + h * h) * s.K;
    for (std::size_t r = 0; r < model.diagonal_slots().size(); ++r)
        s.A.valuePtr()[model.diagonal_slots()[r]] += model.reduced_mass()(Index(r));
    model.reduce(f, s.b);
    s.b *= h;
    return s;
}

void assemble_bench(benchmark::State& state, int n) {
    const Snapshot& s = snapshot(n);
    Box b = make_box(n);
    solve::SparseMatrix K = b.model->make_matrix();
    VecX f;
    b.model->assemble(s.state.x, elasticity::ForceMode::Corotated, &K, &f); // warm rotations
    for (auto _ : state) {
        b.model->assemble(s.state.x, elasticity::ForceMode::Corotated, &K, &f);
        benchmark::DoNotOptimize(K.valuePtr());
    }
    state.counters["us_per_tet"] = benchmark::Counter(double(b.mesh->num_cells()) * 1e-6,
        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void spmv_bench(benchmark::State& state, int n) {
    const Snapshot& s = snapshot(n);
    VecX y;
    for (auto _ : state) {
        solve::multiply_symmetric(s.A, s.b, y);
        benchmark::DoNotOptimize(y.data());
    }
    // Bytes per SpMV: values + row indices + column pointers + x (read once at best) + y.
    const double bytes = double(s.A.nonZeros()) * 12.0 + double(s.A.rows()) * (4 + 8 + 8);
    state.counters["MB"] = bytes * 1e-6;
    state.counters["GBps"] = benchmark::Counter(
        bytes, benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1024);
    state.counters["nnz"] = double(s.A.nonZeros());
}

/// Streaming bandwidth (triad a = b + s c over 3 x 32 MB), for the SpMV floor.
void triad_bench(benchmark::State& state) {
    const Index m = 4 << 20;
    VecX a = VecX::Zero(m), b = VecX::Ones(m), c = VecX::Ones(m);
    for (auto _ : state) {
        a.noalias() = b + 0.5 * c;
        benchmark::DoNotOptimize(a.data());
    }
    state.counters["GBps"] = benchmark::Counter(3.0 * 8.0 * double(m),
        benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1024);
}

/// One preconditioned PCG solve from zero to 1e-6 on the snapshot's system: per iteration cost of
/// each preconditioner. (Solved to convergence: a solve that hits its iteration limit with a
/// lagged factor or AMG hierarchy refactors and goes on, which would count the set-up too.)
void pcg_iteration_bench(
    benchmark::State& state, int n, solve::Preconditioner p, bool hypre_cycle) {
    const Snapshot& s = snapshot(n);
    solve::PcgOptions o;
    o.preconditioner = p;
    o.relative_tolerance = 1e-6;
    o.max_iterations = 5000;
    o.refactor_iterations = 5000;
    o.amg = amg_options();
    if (hypre_cycle)
        o.amg.fused_cycle = false;
    solve::PcgSolver pcg(o);
    pcg.set_coordinates(free_coordinates(*s.box.model, s.state.x));
    VecX x;
    x.setZero(s.b.size());
    pcg.solve(s.A, s.b, x); // set-up (a lagged factor is computed here)
    int iterations = 0;
    for (auto _ : state) {
        x.setZero();
        const solve::PcgResult r = pcg.solve(s.A, s.b, x);
        iterations += r.iterations;
    }
    state.counters["ms_per_it"] = benchmark::Counter(
        double(iterations) * 1e-3, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["its"]
        = double(iterations) / double(std::max<benchmark::IterationCount>(state.iterations(), 1));
}

/// AMG hierarchy set-up on the snapshot's matrix (plus one PCG iteration, negligible beside it).
void amg_setup_bench(benchmark::State& state, int n) {
    const Snapshot& s = snapshot(n);
    solve::PcgOptions o;
    o.preconditioner = solve::Preconditioner::Amg;
    o.relative_tolerance = 1e-30;
    o.max_iterations = 1;
    o.refactor_every = 1;
    o.amg = amg_options();
    solve::PcgSolver pcg(o);
    pcg.set_coordinates(free_coordinates(*s.box.model, s.state.x));
    VecX x;
    for (auto _ : state) {
        x.setZero(s.b.size());
        pcg.solve(s.A, s.b, x);
    }
    state.counters["levels"] = pcg.amg_levels();
}

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    for (int n : { 12, 20, 30 }) {
        const std::string box = "box" + std::to_string(n);
        benchmark::RegisterBenchmark(("Assemble/" + box).c_str(), assemble_bench, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("SpMV/" + box).c_str(), spmv_bench, n)
            ->Unit(benchmark::kMillisecond);
        for (auto [name, p] : { std::pair { "jacobi", solve::Preconditioner::Jacobi },
                 std::pair { "block_jacobi", solve::Preconditioner::BlockJacobi3 },
                 std::pair { "lagged", solve::Preconditioner::LaggedCholesky },
                 std::pair { "ic", solve::Preconditioner::IncompleteCholesky },
                 std::pair { "amg", solve::Preconditioner::Amg },
                 std::pair { "amg_hc", solve::Preconditioner::Amg } })
            benchmark::RegisterBenchmark(("PcgIteration/" + box + "/" + name).c_str(),
                pcg_iteration_bench, n, p, std::string(name) == "amg_hc")
                ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("AmgSetup/" + box).c_str(), amg_setup_bench, n)
            ->Unit(benchmark::kMillisecond);
        SolverOptions direct;
        direct.kind = LinearSolverKind::Cholmod;
        benchmark::RegisterBenchmark(
            ("Step/" + box + "/cholmod").c_str(), run_steps, n, direct, false)
            ->Unit(benchmark::kMillisecond)
            ->Iterations(kTimed);
        for (double tol : { 1e-6, 1e-3, 1e-2, 3e-2, 1e-1, 3e-1 }) {
            char t[16];
            std::snprintf(t, sizeof t, "%.0e", tol);
            for (const Method& m : methods(tol))
                for (bool extrapolate : { false, true })
                    benchmark::RegisterBenchmark(
                        ("Step/" + box + "/" + m.name + (extrapolate ? "+x" : "") + "/tol" + t)
                            .c_str(),
                        run_steps, n, m.options, extrapolate)
                        ->Unit(benchmark::kMillisecond)
                        ->Iterations(kTimed);
        }
    }
    benchmark::RegisterBenchmark("Triad", triad_bench)->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
