// Step time of a polyhedral mesh against tet and hex meshes of about the same node count (issue 4
// item 6). A 0.1 m cube, x = 0 fixed, gravity, E = 10 kPa, nu = 0.45, rho = 1000, beta = 0.01,
// corotated implicit Euler at dt = 0.01 with AMG-preconditioned PCG to 1e-1 (the bench_box
// settings), one thread:
//
//   PolyStep/mvc/<n>, PolyStep/harmonic/<n>: n^3 hex blocks split by n^3 random planes (000
//     Fig. 2, one plane per block on average, seed 7) into convex polyhedra
//   PolyStep/tet/<m>: m^3 blocks x 6 Kuhn tets, m chosen for about the polyhedral node count
//   PolyStep/hex/<m>: m^3 Q1 hexes, likewise
//
// 5 warm-up steps from rest, then 30 timed steps. Counters: med_ms / p90_ms (process CPU time
// per step), asm_ms / slv_ms (medians of the step report's wall times), its, nodes, cells,
// setup_ms (model construction: basis, quadrature and Ke of every cell, CPU), nnz (of K).
#include "polycut/common/stats.hpp"
#include "polycut/cut/random_planes.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"

#include <benchmark/benchmark.h>
#include <cmath>
#include <memory>
#include <string>

using namespace polycut;
using namespace polycut::integrate;

namespace {

constexpr int kWarmup = 5;
constexpr int kTimed = 30;

enum class Kind { Mvc, Harmonic, Tet, Hex };

mesh::Mesh make_mesh(Kind kind, int n) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    switch (kind) {
    case Kind::Tet:
        return mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
    case Kind::Hex:
        return mesh::hex_grid(g);
    default: {
        const mesh::Mesh hexes = mesh::hex_grid(g);
        return cut::split_by_random_planes(hexes, int(hexes.num_cells()), 7);
    }
    }
}

void poly_step(benchmark::State& state, Kind kind, int n) {
    const mesh::Mesh m = make_mesh(kind, n);
    elasticity::Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.45;
    mat.density = 1000;
    mat.rayleigh_stiffness = 0.01;
    basis::BasisOptions b;
    b.poly = kind == Kind::Harmonic ? basis::PolyBasis::Harmonic : basis::PolyBasis::MeanValue;
    std::vector<std::uint8_t> fixed(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        fixed[std::size_t(i)] = std::abs(m.rest[std::size_t(i)].x()) < 1e-9;
    const double t0 = process_cpu_ms();
    elasticity::ElasticModel model(m, mat, b, elasticity::fix_nodes(fixed));
    const double setup = process_cpu_ms() - t0;

    IntegratorOptions o;
    o.kind = IntegratorKind::ImplicitEuler;
    o.dt = 0.01;
    o.force_mode = elasticity::ForceMode::Corotated;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = LinearSolverKind::PcgAmg;
    o.solver.relative_tolerance = 1e-1;
    o.solver.max_iterations = 5000;
    o.solver.refactor_every = 20;
    o.solver.refactor_iterations = 1000;
    std::vector<double> cpu, asm_ms, slv_ms, its;
    for (auto _ : state) {
        Integrator integ(model, o);
        State s = integ.rest_state();
        for (int k = 0; k < kWarmup; ++k)
            integ.step(s);
        for (int k = 0; k < kTimed; ++k) {
            const double c0 = process_cpu_ms();
            const StepReport r = integ.step(s);
            cpu.push_back(process_cpu_ms() - c0);
            asm_ms.push_back(r.assembly_ms);
            slv_ms.push_back(r.solve_ms);
            its.push_back(r.solver_iterations);
            if (r.rolled_back)
                state.SkipWithError("a step was rolled back");
        }
    }
    const Summary sc = summarize(cpu);
    state.counters["med_ms"] = sc.median;
    state.counters["p90_ms"] = sc.p90;
    state.counters["asm_ms"] = summarize(asm_ms).median;
    state.counters["slv_ms"] = summarize(slv_ms).median;
    state.counters["its"] = summarize(its).median;
    state.counters["nodes"] = double(m.num_nodes());
    state.counters["cells"] = double(m.num_cells());
    state.counters["setup_ms"] = setup;
    state.counters["nnz"] = double(model.make_matrix().nonZeros());
}

} // namespace

int main(int argc, char** argv) {
    // Polyhedral meshes of n^3 blocks with one plane each have ~6.6 n^3 nodes (8^3: 3,407,
    // 12^3: 11,250); the tet and hex grids of m^3 blocks have (m + 1)^3 (14^3: 3,375, 21^3:
    // 10,648).
    struct Case {
        const char* name;
        Kind kind;
        int n;
    };
    const Case cases[] = {
        { "mvc", Kind::Mvc, 8 },
        { "harmonic", Kind::Harmonic, 8 },
        { "tet", Kind::Tet, 14 },
        { "hex", Kind::Hex, 14 },
        { "mvc", Kind::Mvc, 12 },
        { "tet", Kind::Tet, 21 },
        { "hex", Kind::Hex, 21 },
    };
    for (const Case& c : cases)
        benchmark::RegisterBenchmark(
            (std::string("PolyStep/") + c.name + "/" + std::to_string(c.n)).c_str(), poly_step,
            c.kind, c.n)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}
