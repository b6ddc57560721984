// Plane splits of cells (000 sec. 5.1): shared edge nodes, face splits seen by both cells,
// volume conservation, convex halves; a non-convex cell the plane crosses twice, in pieces.
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/mesh/builders.hpp"

#include <algorithm>
#include <gtest/gtest.h>

using namespace polycut;

namespace {
mesh::Mesh block(int n, double size = 0.1) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(size);
    g.cells = Eigen::Vector3i(n, n, n);
    return mesh::hex_grid(g);
}
} // namespace

TEST(PlaneSplit, SingleHexThroughMiddle) {
    auto m = block(1, 1.0);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    const auto r = cutter.split_by_plane(Vec3(0.5, 0.5, 0.5), Vec3(1, 0, 0));
    EXPECT_EQ(m.num_cells(), 2);
    EXPECT_EQ(m.num_nodes(), 12); // 4 new nodes on the x-edges
    EXPECT_EQ(r.new_nodes.size(), 4u);
    EXPECT_NEAR(m.cell_volume(0), 0.5, 1e-14);
    EXPECT_NEAR(m.cell_volume(1), 0.5, 1e-14);
    const auto inv
        = cut::check_cut_invariants(m, v0, { .convex_tol = 1e-12, .planarity_tol = 1e-12 });
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    EXPECT_EQ(m.cells[0].shape, mesh::CellShape::Hex);
    EXPECT_EQ(m.cells[1].shape, mesh::CellShape::Hex);
    // New node weights reproduce positions.
    for (const auto& o : r.new_nodes) {
        Vec3 x = Vec3::Zero();
        for (const auto& [n, w] : o.weights)
            x += w * m.rest[std::size_t(n)];
        EXPECT_LT((x - m.rest[std::size_t(o.node)]).norm(), 1e-14);
    }
}

TEST(PlaneSplit, ObliqueThroughGridKeepsConformity) {
    auto m = block(3);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    const auto r = cutter.split_by_plane(Vec3(0.05, 0.047, 0.052), Vec3(1, 0.7, 0.3));
    EXPECT_GT(r.new_cells.size(), 5u);
    const auto inv
        = cut::check_cut_invariants(m, v0, { .convex_tol = 1e-9, .planarity_tol = 1e-9 });
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    EXPECT_LT(inv.volume_error, 1e-12);
    EXPECT_EQ(inv.components, 1);
}

TEST(PlaneSplit, SplitOneCellGivesNeighboursHangingNodes) {
    auto m = block(2);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    const Index one[] = { 0 };
    const auto r = cutter.split_by_plane(Vec3(0.02, 0.02, 0.02), Vec3(1, 1, 1), one);
    EXPECT_EQ(r.new_cells.size(), 1u);
    const auto inv
        = cut::check_cut_invariants(m, v0, { .convex_tol = 1e-9, .planarity_tol = 1e-9 });
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    // Neighbours of cell 0 got nodes on shared edges and changed.
    EXPECT_GT(r.changed_cells.size(), 2u);
}

TEST(PlaneSplit, OpenCellProblemNamesAFlippedFaceAndAnOpenCell) {
    // The check the cut pipeline runs on every cell a cut changed (a broken one fails the cut).
    auto m = block(1, 1.0);
    EXPECT_EQ(cut::open_cell_problem(m, 0), "");
    cut::Cutter cutter(m);
    cutter.split_by_plane(Vec3(0.3, 0.5, 0.5), Vec3(1, 0.2, 0.1));
    for (Index c = 0; c < m.num_cells(); ++c)
        EXPECT_EQ(cut::open_cell_problem(m, c), "") << "cell " << c;
    auto flipped = m;
    const Index f = flipped.cells[0].faces.front();
    std::reverse(
        flipped.faces[std::size_t(f)].nodes.begin(), flipped.faces[std::size_t(f)].nodes.end());
    EXPECT_NE(
        cut::open_cell_problem(flipped, 0).find("twice in the same direction"), std::string::npos);
    auto open = m;
    open.cells[0].faces.pop_back();
    EXPECT_NE(cut::open_cell_problem(open, 0).find("no opposite edge"), std::string::npos);
}

namespace {
/// One cell shaped as a U: five unit squares ([0,3] x [0,1] and the arms [0,1] x [1,2],
/// [2,3] x [1,2] [m]) extruded over z in [0, 1], its top and bottom as those five squares (every
/// face convex, the cell not: as merged cells are).
mesh::Mesh u_cell() {
    std::vector<Vec3> rest;
    for (int z = 0; z <= 1; ++z)
        for (int j = 0; j <= 2; ++j)
            for (int i = 0; i <= 3; ++i)
                rest.emplace_back(i, j, z);
    auto id = [](int i, int j, int z) { return Index(12 * z + 4 * j + i); };
    const std::vector<std::array<int, 2>> outline { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 3, 0 },
        { 3, 1 }, { 3, 2 }, { 2, 2 }, { 2, 1 }, { 1, 1 }, { 1, 2 }, { 0, 2 }, { 0, 1 } };
    std::vector<std::vector<Index>> faces;
    for (std::size_t k = 0; k < outline.size(); ++k) { // counterclockwise: outward on the right
        const auto a = outline[k], b = outline[(k + 1) % outline.size()];
        faces.push_back(
            { id(a[0], a[1], 0), id(b[0], b[1], 0), id(b[0], b[1], 1), id(a[0], a[1], 1) });
    }
    for (const auto& [i, j] :
        std::vector<std::array<int, 2>> { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 0, 1 }, { 2, 1 } }) {
        faces.push_back({ id(i, j, 1), id(i + 1, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1) });
        faces.push_back({ id(i, j + 1, 0), id(i + 1, j + 1, 0), id(i + 1, j, 0), id(i, j, 0) });
    }
    return mesh::Mesh::from_polyhedra(std::move(rest), { faces });
}
} // namespace

TEST(PlaneSplit, ANonConvexCellCrossedTwiceFallsIntoThreePieces) {
    // A plane across both arms of the U leaves two holes: the base on one side, the two arm
    // tips on the other, each a cell, with a face between each tip and the base.
    for (const double sign : { 1.0, -1.0 }) {
        auto m = u_cell();
        const double v0 = m.rest_volume();
        ASSERT_NEAR(v0, 5.0, 1e-12);
        cut::Cutter cutter(m);
        const auto r = cutter.split_by_plane(Vec3(0.5, 1.5, 0.5), Vec3(0, sign, 0));
        ASSERT_EQ(m.num_cells(), 3) << "sign " << sign;
        EXPECT_EQ(r.new_cells.size(), 2u);
        std::vector<double> volumes;
        for (Index c = 0; c < m.num_cells(); ++c)
            volumes.push_back(m.cell_volume(c));
        std::sort(volumes.begin(), volumes.end());
        EXPECT_NEAR(volumes[0], 0.5, 1e-12);
        EXPECT_NEAR(volumes[1], 0.5, 1e-12);
        EXPECT_NEAR(volumes[2], 4.0, 1e-12);
        int interfaces = 0;
        for (const auto& f : m.faces)
            interfaces += !f.boundary();
        EXPECT_EQ(interfaces, 2);
        // The base stays non-convex (a U with short arms): no convexity check here.
        const auto inv
            = cut::check_cut_invariants(m, v0, { .convex_tol = 1e9, .planarity_tol = 1e-12 });
        EXPECT_TRUE(inv.ok()) << inv.first_problem;
        EXPECT_EQ(inv.components, 1);
    }
}
