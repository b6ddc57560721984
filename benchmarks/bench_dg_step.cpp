// Step time of DG (seed 003, issue 13 item 9) against P1, Q1 and mvc at about equal DOFs, and the
// DG linear solvers against each other. Same problem as bench_poly_step: a 0.1 m cube, x = 0
// fixed (DG: weakly, Nitsche), gravity, E = 10 kPa, nu = 0.45, rho = 1000, beta = 0.01,
// corotated implicit Euler at dt = 0.01, one thread.
//
//   DgStep/<method>/<solver>[@tolerance]/<n>: n^3 cells (DG p=1, p=2 and Q1 hexes, P1 Kuhn-6
//   blocks, mvc
//     n^3 blocks split by n^3 random planes)
//
// 5 warm-up steps from rest, then 30 timed steps. Counters: med_ms / p99_ms (process CPU time per
// step), asm_ms / slv_ms (medians of the report's wall times), its (PCG iterations), dofs, nnz,
// setup_ms (model construction, CPU), and err: the largest displacement difference after the 35
// steps from the same model stepped with CHOLMOD (exact solves), over the largest displacement
// ("equal accuracy" in the displacement, not the residual).
#include "polycut/common/stats.hpp"
#include "polycut/cut/random_planes.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/builders.hpp"

#include <benchmark/benchmark.h>
#include <cmath>
#include <map>
#include <memory>
#include <string>

using namespace polycut;
using namespace polycut::integrate;

namespace {

constexpr int kWarmup = 5;
constexpr int kTimed = 30;

enum class Kind { DgP1, DgP2, Tet, Hex, Mvc };

mesh::Mesh make_mesh(Kind kind, int n) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    if (kind == Kind::Tet)
        return mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
    const mesh::Mesh hexes = mesh::hex_grid(g);
    if (kind == Kind::Mvc)
        return cut::split_by_random_planes(hexes, int(hexes.num_cells()), 7);
    return hexes;
}

elasticity::Material material() {
    elasticity::Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.45;
    mat.density = 1000;
    mat.rayleigh_stiffness = 0.01;
    return mat;
}

IntegratorOptions options(LinearSolverKind solver, double tolerance = 1e-1) {
    IntegratorOptions o;
    o.kind = IntegratorKind::ImplicitEuler;
    o.dt = 0.01;
    o.force_mode = elasticity::ForceMode::Corotated;
    o.gravity = Vec3(0, 0, -9.81);
    o.solver.kind = solver;
    o.solver.relative_tolerance = tolerance;
    o.solver.max_iterations = 5000;
    o.solver.refactor_every = 20;
    o.solver.refactor_iterations = 1000;
    return o;
}

struct Built {
    mesh::Mesh mesh;
    std::unique_ptr<elasticity::Model> model;
};

Built build(Kind kind, int n) {
    Built b;
    b.mesh = make_mesh(kind, n);
    const mesh::Mesh& m = b.mesh;
    if (kind == Kind::DgP1 || kind == Kind::DgP2) {
        std::vector<Index> fixed;
        for (Index f = 0; f < m.num_faces(); ++f) {
            const mesh::Face& face = m.faces[std::size_t(f)];
            bool on = face.boundary();
            for (Index v : face.nodes)
                on = on && std::abs(m.rest[std::size_t(v)].x()) < 1e-9;
            if (on)
                fixed.push_back(f);
        }
        dg::DgOptions o;
        o.degree = kind == Kind::DgP1 ? 1 : 2;
        b.model = std::make_unique<dg::DgModel>(m, material(), o, fixed);
        return b;
    }
    std::vector<std::uint8_t> fixed(std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        fixed[std::size_t(i)] = std::abs(m.rest[std::size_t(i)].x()) < 1e-9;
    b.model = std::make_unique<elasticity::ElasticModel>(
        m, material(), basis::BasisOptions {}, elasticity::fix_nodes(fixed));
    return b;
}

/// Final state after kWarmup + kTimed steps with exact solves, per (kind, n): the reference.
const MatX3& reference(Kind kind, int n) {
    static std::map<std::pair<int, int>, MatX3> cache;
    auto [it, fresh] = cache.try_emplace({ int(kind), n });
    if (fresh) {
        Built b = build(kind, n);
        Integrator integ(*b.model, options(LinearSolverKind::Cholmod));
        State s = integ.rest_state();
        for (int k = 0; k < kWarmup + kTimed; ++k)
            integ.step(s);
        it->second = s.x;
    }
    return it->second;
}

void dg_step(benchmark::State& state, Kind kind, LinearSolverKind solver, double tol, int n) {
    const double t0 = process_cpu_ms();
    Built b = build(kind, n);
    const double setup = process_cpu_ms() - t0;
    std::vector<double> cpu, asm_ms, slv_ms, its;
    MatX3 final_x;
    for (auto _ : state) {
        Integrator integ(*b.model, options(solver, tol));
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
        final_x = s.x;
    }
    MatX3 X0;
    b.model->rest_rows(X0);
    const MatX3& ref = reference(kind, n);
    const double scale = (ref - X0).rowwise().norm().maxCoeff();
    const Summary sc = summarize(cpu);
    state.counters["med_ms"] = sc.median;
    state.counters["p99_ms"] = sc.p99;
    state.counters["asm_ms"] = summarize(asm_ms).median;
    state.counters["slv_ms"] = summarize(slv_ms).median;
    state.counters["its"] = summarize(its).median;
    state.counters["dofs"] = double(3 * b.model->num_rows());
    state.counters["setup_ms"] = setup;
    state.counters["nnz"] = double(b.model->make_matrix().nonZeros());
    state.counters["err"] = (final_x - ref).rowwise().norm().maxCoeff() / scale;
}

} // namespace

int main(int argc, char** argv) {
    // About 10-12k DOFs each: DG p=1 10^3 cells (12,000, the issue's 1,000-cell organ), DG p=2
    // 7^3 (10,290), P1 and Q1 15^3 (12,288), mvc 8^3 blocks (~10,200).
    struct Case {
        const char* name;
        Kind kind;
        const char* solver_name;
        LinearSolverKind solver;
        double tolerance; ///< PCG relative tolerance
        int n;
    };
    const Case cases[] = {
        { "dg_p1", Kind::DgP1, "cholmod", LinearSolverKind::Cholmod, 0, 10 },
        { "dg_p1", Kind::DgP1, "jacobi", LinearSolverKind::PcgJacobi, 1e-3, 10 },
        { "dg_p1", Kind::DgP1, "block_jacobi", LinearSolverKind::PcgBlockJacobi, 1e-3, 10 },
        { "dg_p1", Kind::DgP1, "cell_block_jacobi", LinearSolverKind::PcgCellBlockJacobi, 1e-3,
            10 },
        { "dg_p1", Kind::DgP1, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-1, 10 },
        { "dg_p1", Kind::DgP1, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-2, 10 },
        { "dg_p1", Kind::DgP1, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-3, 10 },
        { "dg_p1", Kind::DgP1, "amg", LinearSolverKind::PcgAmg, 1e-3, 10 },
        { "dg_p1", Kind::DgP1, "two_level", LinearSolverKind::PcgTwoLevel, 1e-1, 10 },
        { "dg_p1", Kind::DgP1, "two_level", LinearSolverKind::PcgTwoLevel, 1e-2, 10 },
        { "dg_p1", Kind::DgP1, "two_level", LinearSolverKind::PcgTwoLevel, 1e-3, 10 },
        { "dg_p2", Kind::DgP2, "cholmod", LinearSolverKind::Cholmod, 0, 7 },
        { "dg_p2", Kind::DgP2, "block_jacobi", LinearSolverKind::PcgBlockJacobi, 1e-3, 7 },
        { "dg_p2", Kind::DgP2, "cell_block_jacobi", LinearSolverKind::PcgCellBlockJacobi, 1e-3, 7 },
        { "dg_p2", Kind::DgP2, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-1, 7 },
        { "dg_p2", Kind::DgP2, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-2, 7 },
        { "dg_p2", Kind::DgP2, "lagged_cholesky", LinearSolverKind::PcgLagged, 1e-3, 7 },
        { "dg_p2", Kind::DgP2, "two_level", LinearSolverKind::PcgTwoLevel, 1e-3, 7 },
        { "tet", Kind::Tet, "amg", LinearSolverKind::PcgAmg, 1e-1, 15 },
        { "hex", Kind::Hex, "amg", LinearSolverKind::PcgAmg, 1e-1, 15 },
        { "mvc", Kind::Mvc, "amg", LinearSolverKind::PcgAmg, 1e-1, 8 },
    };
    for (const Case& c : cases)
        benchmark::RegisterBenchmark(
            (std::string("DgStep/") + c.name + "/" + c.solver_name
                + (c.tolerance > 0 ? "@" + std::to_string(c.tolerance).substr(0, 5) : std::string())
                + "/" + std::to_string(c.n))
                .c_str(),
            dg_step, c.kind, c.solver, c.tolerance, c.n)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}
