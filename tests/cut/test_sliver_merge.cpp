// Sliver merging (000 sec. 4): a plane passing just beyond the snapping distance of a grid node
// cuts a tiny corner off every cell around it; each corner merges back into its sibling, so no
// cell below sliver_volume of its neighbours remains, and volume and invariants hold exactly.
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {
mesh::Mesh grid() {
    mesh::BoxGrid g;
    g.hi = Vec3(0.03, 0.03, 0.03);
    g.cells = { 3, 3, 3 };
    return mesh::hex_grid(g);
}

// Smallest cell volume over the largest [dimensionless].
double min_volume_ratio(const mesh::Mesh& m) {
    double lo = 1e300, hi = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        lo = std::min(lo, m.cell_volume(c));
        hi = std::max(hi, m.cell_volume(c));
    }
    return lo / hi;
}

// The plane x + y + z = 3 X0 - t sqrt(3) h cuts a corner tet of legs ~ 3 t h off each of the
// 8 cells around the grid node X0 = (0.01, 0.01, 0.01): volume ratio ~ (3t)^3 / 6 = 4.5e-6 for
// t = 0.01, while the node is 0.01 h from the plane (beyond the 1e-3 h snap).
cut::CutReport cut_corners(mesh::Mesh& m, bool merge) {
    cut::CutOptions opt;
    opt.merge_slivers = merge;
    cut::Cutter cutter(m, opt);
    const double h = 0.01, t = 0.01;
    const Vec3 n = Vec3(1, 1, 1).normalized();
    const Vec3 point = Vec3(0.01, 0.01, 0.01) - t * h * n;
    return cutter.split_by_plane(point, n);
}
} // namespace

TEST(SliverMerge, CornerSliversMergeBackIntoTheirSiblings) {
    mesh::Mesh kept = grid();
    const double v0 = kept.rest_volume();
    const cut::CutReport r0 = cut_corners(kept, false);
    EXPECT_EQ(r0.slivers_merged, 0);
    EXPECT_LT(min_volume_ratio(kept), 1e-4); // the slivers are there without merging

    mesh::Mesh m = grid();
    const cut::CutReport r = cut_corners(m, true);
    EXPECT_GT(r.slivers_merged, 0);
    EXPECT_EQ(r.slivers_merged + r.cells_after, r0.cells_after);
    EXPECT_GT(min_volume_ratio(m), 1e-3);
    const cut::CutInvariants inv = cut::check_cut_invariants(m, v0);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    EXPECT_LE(inv.volume_error, 1e-12);
    EXPECT_LE(inv.max_convexity_violation, 1e-9); // unions of siblings are the old cells
    // The report renumbers consistently: new cells and parents are valid ids after the call.
    for (const cut::CellOrigin& o : r.new_cells) {
        EXPECT_GE(o.cell, 0);
        EXPECT_LT(o.cell, m.num_cells());
    }
    for (const cut::NodeOrigin& o : r.new_nodes) {
        EXPECT_GE(o.parent_cell, 0);
        EXPECT_LT(o.parent_cell, m.num_cells());
    }
    for (Index c : r.changed_cells) {
        EXPECT_GE(c, 0);
        EXPECT_LT(c, m.num_cells());
    }
}

TEST(SliverMerge, MergedMeshCutsOnAndStaysValid) {
    // Cut the merged mesh again through the same region: still valid, volume exact.
    mesh::Mesh m = grid();
    const double v0 = m.rest_volume();
    cut_corners(m, true);
    cut::Cutter cutter(m);
    const cut::Triangle a { Vec3(-0.01, 0.012, -0.01), Vec3(0.05, 0.012, -0.01),
        Vec3(0.05, 0.012, 0.05) };
    const cut::Triangle b { Vec3(-0.01, 0.012, -0.01), Vec3(0.05, 0.012, 0.05),
        Vec3(-0.01, 0.012, 0.05) };
    const std::vector<cut::Triangle> tris { a, b };
    cutter.cut(tris);
    const cut::CutInvariants inv = cut::check_cut_invariants(m, v0);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    EXPECT_EQ(inv.components, 2);
}
