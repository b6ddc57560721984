// Timing of progressive sweep cuts on a 20^3 hex block (10 cm): a vertical blade advancing in
// 1 mm steps across the block, 2 sweep triangles per step. Prints per-triangle-pair timings.
#include "polycut/common/stats.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/mesh/builders.hpp"

#include <cstdio>

using namespace polycut;

int main() {
    mesh::BoxGrid g;
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(20, 20, 20);
    auto m = mesh::hex_grid(g);
    Stopwatch setup;
    cut::Cutter cutter(m);
    const double setup_ms = setup.ms();
    std::vector<double> ms;
    for (double y = -0.005; y < 0.105; y += 0.001) {
        const double x = 0.0503 + 0.01 * std::sin(20 * y);
        const double x1 = 0.0503 + 0.01 * std::sin(20 * (y + 0.001));
        const Vec3 a0(x, y, 0.11), b0(x, y, 0.04), a1(x1, y + 0.001, 0.11), b1(x1, y + 0.001, 0.04);
        const std::vector<cut::Triangle> tris { { a0, b0, b1 }, { a0, b1, a1 } };
        ms.push_back(cutter.cut(tris).elapsed_ms / 2);
    }
    const auto s = summarize(ms);
    std::printf(
        "20^3 hexes: cutter setup %.2f ms; per sweep triangle: median %.3f ms, p90 %.3f ms, "
        "max %.3f ms over %ld triangle pairs; final %d cells, %d nodes\n",
        setup_ms, s.median, s.p90, s.max, s.count, m.num_cells(), m.num_nodes());
    return 0;
}
