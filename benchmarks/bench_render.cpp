// Off-screen render throughput (issue 7 item 6): a ~50k-triangle surface at 640x480 on llvmpipe,
// target 60 fps. Reports the median and p95 wall frame time [ms] over all iterations and, side
// by side, the process CPU time per frame over all threads (cpu_ms_per_frame).
// Threads: llvmpipe uses LP_NUM_THREADS (default: one per core); compare
//   LP_NUM_THREADS=1 ./bench_render   and   LP_NUM_THREADS=2 ./bench_render
#include "polycut/common/stats.hpp"
#include "polycut/render/renderer.hpp"

#include <benchmark/benchmark.h>
#include <cmath>
#include <numbers>

namespace {

using namespace polycut;
using namespace polycut::render;

/// A bumpy sphere with slices x stacks quads, minus the degenerate pole triangles; an equatorial
/// band is tagged cut, so both colours and a tag boundary are drawn.
struct Blob {
    std::vector<float> positions;
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint8_t> tags;

    Blob(int slices, int stacks, double radius) {
        for (int j = 0; j <= stacks; ++j)
            for (int i = 0; i < slices; ++i) {
                const double theta = std::numbers::pi * j / stacks;
                const double phi = 2 * std::numbers::pi * i / slices;
                const double r = radius
                    * (1 + 0.08 * std::sin(3 * phi) * std::sin(2 * theta)
                        + 0.05 * std::cos(5 * theta));
                positions.insert(positions.end(),
                    { float(r * std::sin(theta) * std::cos(phi)),
                        float(r * std::sin(theta) * std::sin(phi)), float(r * std::cos(theta)) });
            }
        auto id = [&](int i, int j) { return std::uint32_t(j * slices + i % slices); };
        for (int j = 0; j < stacks; ++j)
            for (int i = 0; i < slices; ++i) {
                const std::uint8_t tag = std::abs(2 * j - stacks) < stacks / 10 ? 2 : 1;
                if (j > 0) {
                    triangles.insert(triangles.end(), { id(i, j), id(i + 1, j), id(i + 1, j + 1) });
                    tags.push_back(tag);
                }
                if (j < stacks - 1) {
                    triangles.insert(triangles.end(), { id(i, j), id(i + 1, j + 1), id(i, j + 1) });
                    tags.push_back(tag);
                }
            }
    }

    SurfaceArrays arrays() const { return { positions, triangles, tags }; }
};

const Blob& blob_50k() {
    static const Blob blob(160, 158, 0.05); // 2 * 160 * 157 = 50240 triangles
    return blob;
}

// process_cpu_ms() (all threads: llvmpipe rasterizes on worker threads) and thread_cpu_ms() (the
// GL API thread: llvmpipe shades vertices and bins triangles there) from polycut/common/stats.hpp.

void report(benchmark::State& state, const std::vector<double>& times_ms, std::size_t triangles,
    double cpu_ms) {
    const Summary s = summarize(times_ms);
    // Wall-clock figures suffer on a shared machine; CPU per frame over all threads less so.
    state.counters["cpu_ms_per_frame"] = cpu_ms / double(times_ms.size());
    state.counters["median_ms"] = s.median;
    state.counters["p95_ms"] = s.p95;
    state.counters["fps_at_median"] = 1000.0 / s.median;
    state.counters["triangles"] = double(triangles);
}

/// Settings of one benchmark configuration.
struct Variant {
    int msaa = 4;
    bool wireframe = false;
    bool cull = false;
    bool profile = false;
};

/// Full frame: validation, shading normals, upload, draw, MSAA resolve and RGBA read-back.
/// With `profile`, the renderer waits after each GL phase and the phase medians are reported
/// as counters (a little slower in total than an unprofiled frame).
void render_frame(benchmark::State& state, const Variant& variant) {
    const Blob& blob = blob_50k();
    RenderConfig config;
    config.width = 640;
    config.height = 480;
    config.msaa_samples = variant.msaa;
    config.wireframe = variant.wireframe;
    config.cull_back_faces = variant.cull;
    config.profile = variant.profile;
    Renderer renderer(config);
    DrawList scene { blob.arrays(), {}, {}, {}, {} };
    const auto [lo, hi] = bounds(blob.positions);
    const Camera camera = frame(lo, hi, 640.0 / 480.0);
    Image image;
    renderer.render(scene, camera, image); // warm-up: shader JIT, buffer allocation
    std::vector<double> times;
    std::vector<std::vector<double>> phases(8);
    const double cpu_start = process_cpu_ms();
    const double thread_start = thread_cpu_ms();
    for (auto _ : state) {
        Stopwatch watch;
        renderer.render(scene, camera, image);
        benchmark::DoNotOptimize(image.rgba.data());
        times.push_back(watch.ms());
        const RenderTimings& t = renderer.timings();
        const double values[8] = { t.validate_ms, t.normals_ms, t.fill_ms, t.upload_ms, t.submit_ms,
            t.raster_ms, t.resolve_ms, t.read_ms };
        for (int k = 0; k < 8; ++k)
            phases[std::size_t(k)].push_back(values[k]);
    }
    report(state, times, blob.triangles.size() / 3, process_cpu_ms() - cpu_start);
    state.counters["api_thread_cpu_ms"] = (thread_cpu_ms() - thread_start) / double(times.size());
    if (variant.profile) {
        const char* names[8] = { "validate_ms", "normals_ms", "fill_ms", "upload_ms", "submit_ms",
            "raster_ms", "resolve_ms", "read_ms" };
        for (int k = 0; k < 8; ++k)
            state.counters[names[k]] = summarize(phases[std::size_t(k)]).median;
    }
}

/// Argument: MSAA samples (0 = off). Two-sided (no culling), as for arbitrary input.
void BM_Render50k(benchmark::State& state) {
    render_frame(state, { int(state.range(0)), false, false, false });
}
/// Back faces culled (closed, consistently oriented surfaces such as the simulation's).
void BM_Render50k_Cull(benchmark::State& state) {
    render_frame(state, { int(state.range(0)), false, true, false });
}
/// Where the time goes: phase medians (glFinish after each GL phase).
void BM_Render50k_Profile(benchmark::State& state) {
    render_frame(state, { int(state.range(0)), false, state.range(1) != 0, true });
}
/// Debug view: every triangle edge as a line on top (the edge list is rebuilt every frame).
void BM_Render50k_Wireframe(benchmark::State& state) {
    render_frame(state, { 4, true, false, false });
}

/// The CPU part alone: shading normals split at creases and tags.
void BM_ShadedMesh50k(benchmark::State& state) {
    const Blob& blob = blob_50k();
    ShadedMesh mesh;
    build_shaded_mesh(blob.arrays(), 35, mesh);
    std::vector<double> times;
    const double cpu_start = process_cpu_ms();
    for (auto _ : state) {
        Stopwatch watch;
        build_shaded_mesh(blob.arrays(), 35, mesh);
        benchmark::DoNotOptimize(mesh.normals.data());
        times.push_back(watch.ms());
    }
    report(state, times, blob.triangles.size() / 3, process_cpu_ms() - cpu_start);
}

BENCHMARK(BM_Render50k)
    ->ArgName("msaa")
    ->Arg(4)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0)
    ->UseRealTime();
BENCHMARK(BM_Render50k_Cull)
    ->ArgName("msaa")
    ->Arg(4)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0)
    ->UseRealTime();
BENCHMARK(BM_Render50k_Profile)
    ->ArgNames({ "msaa", "cull" })
    ->Args({ 4, 0 })
    ->Args({ 0, 0 })
    ->Args({ 0, 1 })
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0)
    ->UseRealTime();
BENCHMARK(BM_Render50k_Wireframe)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_ShadedMesh50k)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
