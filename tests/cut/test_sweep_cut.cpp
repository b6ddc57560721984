// Sweep-triangle cuts (000 sec. 5.2): separation, crack fronts, pockets, invariants.
#include "polycut/common/error.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {
mesh::Mesh block(int n, double size = 0.1, bool tets = false)
{
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(size);
    g.cells = Eigen::Vector3i(n, n, n);
    return tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
}

void expect_ok(const mesh::Mesh& m, double v0)
{
    const auto inv = cut::check_cut_invariants(m, v0);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
}
} // namespace

TEST(SweepCut, BlockCutInHalves)
{
    auto m = block(4);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    // Two triangles covering the plane x = 0.051 well beyond the block.
    const cut::Triangle t1 { Vec3(0.051, -0.1, -0.1), Vec3(0.051, 0.3, -0.1), Vec3(0.051, 0.3, 0.3) };
    const cut::Triangle t2 { Vec3(0.051, -0.1, -0.1), Vec3(0.051, 0.3, 0.3), Vec3(0.051, -0.1, 0.3) };
    const cut::Triangle tris[] = { t1, t2 };
    const auto r = cutter.cut(tris);
    expect_ok(m, v0);
    EXPECT_EQ(m.count_components(), 2);
    EXPECT_EQ(r.new_cells.size(), 16u);
    EXPECT_EQ(r.pockets, 0);
}
