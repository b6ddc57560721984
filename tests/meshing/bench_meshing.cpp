// Meshing time and size of CGAL Mesh_3 for the sphere (r = 5 cm) and the organ-like blob at a
// few cell sizes. Counters: nodes, tets. Run: bench_meshing --benchmark_repetitions=3.
#include "polycut/meshing/implicit.hpp"

#include <benchmark/benchmark.h>

using namespace polycut;
using namespace polycut::meshing;

namespace {

void run(benchmark::State& state, const ImplicitShape& shape) {
    MeshingOptions o;
    o.cell_size = double(state.range(0)) * 1e-3;
    Index nodes = 0, cells = 0;
    for (auto _ : state) {
        const mesh::Mesh m = mesh_implicit(shape, o);
        nodes = m.num_nodes();
        cells = m.num_cells();
        benchmark::DoNotOptimize(nodes);
    }
    state.counters["nodes"] = double(nodes);
    state.counters["tets"] = double(cells);
}

void BM_Sphere(benchmark::State& state) {
    run(state, ImplicitShape::sphere(0.05));
}
void BM_Blob(benchmark::State& state) {
    run(state, ImplicitShape::blob());
}

} // namespace

// Argument: cell size [mm].
BENCHMARK(BM_Sphere)->Arg(15)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Blob)->Arg(15)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
