// Face-snapping cut timings on a 10^3-block Kuhn mesh (6000 tets): a blade sweeping through the
// block in 1 mm steps, one call per sweep triangle (one per tick). Prints the median and max time
// per triangle; not a test.
#include "polycut/common/stats.hpp"
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/mesh/builders.hpp"

#include <iostream>
#include <vector>

using namespace polycut;

int main() {
    mesh::BoxGrid g;
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(10, 10, 10);
    auto m = mesh::tet_grid(g);
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m);
    const Vec3 n = Vec3(1, 0.15, 0.05).normalized();
    const Vec3 t = (Vec3::UnitY() - n.y() * n).normalized();
    const Vec3 b0(0.0437, -0.005, -0.02);
    const Vec3 b1 = b0 + 0.14 * n.cross(t).normalized();
    const Vec3 step = 1e-3 * t;
    std::vector<double> ms;
    Index faces = 0, collapsed = 0;
    for (int i = 0; i < 120; ++i) {
        const Vec3 p = b0 + double(i) * step, q = b1 + double(i) * step;
        const cut::Triangle tris[2]
            = { { p, q, Vec3(q + step) }, { p, Vec3(q + step), Vec3(p + step) } };
        for (const auto& tri : tris) {
            const auto r = cutter.cut(std::span(&tri, 1));
            ms.push_back(r.elapsed_ms);
            faces += cutter.stats().faces_dissected;
            collapsed += cutter.stats().edges_collapsed;
        }
    }
    const auto s = summarize(ms);
    std::cout << "snap cut, 6000 tets, " << s.count << " sweep triangles: median " << s.median
              << " ms, p90 " << s.p90 << " ms, max " << s.max << " ms per triangle; " << faces
              << " faces dissected, " << collapsed << " collapses, components "
              << m.count_components() << ", volume change " << std::abs(m.rest_volume() - v0) / v0
              << "\n";
}
