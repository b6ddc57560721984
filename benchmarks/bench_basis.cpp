// Per-cell set-up cost of the polyhedral bases (issue 4 item 6): shape functions + quadrature +
// Ke = sum_q w_q B_q^T C B_q, against the cell's node count (4 to 40), for mean value
// coordinates with the heuristic rule (000 eq. 14-16) and the reference rule (degree 2), and for
// the harmonic basis (001, Gauss degree 2) with the default options and with 001's settings.
// Targets: < 1 ms (mvc heuristic) and < 10 ms (harmonic) for a typical cut cell of 8-16 nodes.
#include "../tests/basis/polyhedral_cells.hpp"
#include "polycut/basis/harmonic.hpp"
#include "polycut/basis/mean_value.hpp"

#include <benchmark/benchmark.h>
#include <numbers>

namespace {
using namespace polycut;
using namespace polycut::basis;
using namespace polycut::basis::testing;

/// A cell with about `nodes` nodes: tet, cube, cut cube, truncated octahedron, or a prism over
/// a regular polygon (2k nodes).
CellGeometry cell_with(int nodes) {
    switch (nodes) {
    case 4:
        return unit_tet();
    case 8:
        return cube();
    case 10:
        return cut_cube();
    case 24:
        return truncated_octahedron();
    default: {
        std::vector<Vec3> p;
        const int k = nodes / 2;
        for (int z = 0; z < 2; ++z)
            for (int i = 0; i < k; ++i) {
                const double a = 2 * std::numbers::pi * i / k;
                p.emplace_back(std::cos(a), std::sin(a), 0.8 * z);
            }
        return convex_cell(p);
    }
    }
}

const auto kC = isotropic_c(1e5, 0.4);

void BM_MvcHeuristic(benchmark::State& state) {
    const auto geo = cell_with(int(state.range(0)));
    for (auto _ : state) {
        const auto ci = MeanValueCell(geo).integrate(MvcRule::Heuristic);
        benchmark::DoNotOptimize(stiffness(ci, kC));
    }
    state.counters["nodes"] = double(geo.nodes.size());
}

void BM_MvcReference(benchmark::State& state) {
    const auto geo = cell_with(int(state.range(0)));
    for (auto _ : state) {
        const auto ci = MeanValueCell(geo).integrate(MvcRule::Reference, 2);
        benchmark::DoNotOptimize(stiffness(ci, kC));
    }
    state.counters["nodes"] = double(geo.nodes.size());
}

void BM_Harmonic(benchmark::State& state) {
    const auto geo = cell_with(int(state.range(0)));
    Index kernels = 0;
    for (auto _ : state) {
        const HarmonicCell cell(geo);
        kernels = cell.num_kernels();
        const auto ci = cell.integrate({ HarmonicRule::Gauss, 2 });
        benchmark::DoNotOptimize(stiffness(ci, kC));
    }
    state.counters["nodes"] = double(geo.nodes.size());
    state.counters["kernels"] = double(kernels);
}

/// The set-up before the solver and sampling changes (001's settings: xi = 0.1, faces sampled
/// as densely as edges, Householder QR), for the before/after table of docs/perf.md.
void BM_HarmonicPaperQR(benchmark::State& state) {
    const auto geo = cell_with(int(state.range(0)));
    HarmonicOptions options;
    options.offset = 0.1;
    options.face_spacing = 1.0;
    options.solver = HarmonicSolver::QR;
    Index kernels = 0;
    for (auto _ : state) {
        const HarmonicCell cell(geo, options);
        kernels = cell.num_kernels();
        const auto ci = cell.integrate({ HarmonicRule::Gauss, 2 });
        benchmark::DoNotOptimize(stiffness(ci, kC));
    }
    state.counters["nodes"] = double(geo.nodes.size());
    state.counters["kernels"] = double(kernels);
}

void sizes(benchmark::internal::Benchmark* b) {
    for (int n : { 4, 8, 10, 12, 16, 24, 32, 40 })
        b->Arg(n);
    b->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
}

BENCHMARK(BM_MvcHeuristic)->Apply(sizes);
BENCHMARK(BM_MvcReference)->Apply(sizes);
BENCHMARK(BM_Harmonic)->Apply(sizes)->MinTime(0.05);
BENCHMARK(BM_HarmonicPaperQR)->Apply(sizes)->MinTime(0.05);
} // namespace

BENCHMARK_MAIN();
