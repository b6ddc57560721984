// Meshing time and size of CGAL Mesh_3 for the sphere (r = 5 cm) and the organ-like blob at a
// few cell sizes, and of the surface-file pipeline (read, repair, Mesh_3 with perturb and exude)
// on the shipped defective organ surface. Counters: nodes, tets, and for the pipeline the
// repair and Mesh_3 times [ms] and the tets' smallest dihedral angle [deg], 1st-percentile
// radius ratio and sliver count. Run: bench_meshing --benchmark_repetitions=3.
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/surface_file.hpp"

#include <benchmark/benchmark.h>
#include <string>

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

/// assets/meshes/liver_defects.off through mesh_surface_file(); second argument: the repair
/// mode (0 auto, which repairs it with PMP; 1 wrap).
void BM_DefectiveOrganFile(benchmark::State& state) {
    SurfaceFileOptions o;
    o.meshing.cell_size = double(state.range(0)) * 1e-3;
    o.repair.mode = state.range(1) == 0 ? RepairMode::Auto : RepairMode::Wrap;
    o.progress = nullptr;
    const std::string path = std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/liver_defects.off";
    SurfaceFileMesh out;
    for (auto _ : state) {
        out = mesh_surface_file(path, o);
        benchmark::DoNotOptimize(out.mesh.rest.data());
    }
    state.counters["nodes"] = double(out.mesh.num_nodes());
    state.counters["tets"] = double(out.mesh.num_cells());
    state.counters["repair_ms"] = out.repair.time_ms;
    state.counters["mesh3_ms"] = out.mesh_ms;
    state.counters["min_dihedral"] = out.quality.min_dihedral_deg;
    state.counters["rr_p1"] = out.quality.radius_ratio_p1;
    state.counters["slivers"] = double(out.quality.slivers);
    state.counters["dV_pct"] = 100 * out.repair.volume_change;
}

} // namespace

// Argument: cell size [mm].
BENCHMARK(BM_Sphere)->Arg(15)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Blob)->Arg(15)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);
// Arguments: cell size [mm], repair mode (0 auto, 1 wrap).
BENCHMARK(BM_DefectiveOrganFile)
    ->Args({ 8, 0 })
    ->Args({ 4, 0 })
    ->Args({ 3, 0 })
    ->Args({ 4, 1 })
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
