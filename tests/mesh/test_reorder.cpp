// Node and cell numbering for locality (mesh/reorder.hpp): a permutation that keeps the mesh
// valid (volumes, faces, orientation) and shrinks the node graph's bandwidth.
#include "polycut/common/error.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/reorder.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace polycut;
using namespace polycut::mesh;

namespace {
/// A 6 x 5 x 4 Kuhn tet grid with its nodes shuffled (as a mesh generator leaves them).
Mesh shuffled_grid() {
    BoxGrid g;
    g.hi = Vec3(0.06, 0.05, 0.04);
    g.cells = { 6, 5, 4 };
    Mesh m = tet_grid(g);
    std::vector<Index> perm(m.rest.size());
    std::iota(perm.begin(), perm.end(), Index(0));
    std::mt19937 rng(7);
    std::shuffle(perm.begin(), perm.end(), rng);
    renumber_nodes(m, perm);
    return m;
}
} // namespace

TEST(Reorder, RcmIsAPermutationThatShrinksTheBandwidth) {
    Mesh m = shuffled_grid();
    const double volume = m.rest_volume();
    const Index before = node_bandwidth(m);
    const std::vector<Index> order = reorder_for_locality(m);
    std::vector<Index> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size(); ++i)
        ASSERT_EQ(sorted[i], Index(i));
    const Index after = node_bandwidth(m);
    // 7 x 6 x 5 nodes: a banded order has bandwidth ~ one layer of nodes (42 + 7 + 1 in grid
    // order); the shuffled one spans nearly the whole array (210 nodes).
    EXPECT_GT(before, 150);
    EXPECT_LE(after, 60);
    EXPECT_NO_THROW(validate(m));
    EXPECT_NEAR(m.rest_volume(), volume, 1e-15);
    for (Index c = 0; c < m.num_cells(); ++c)
        EXPECT_GT(m.cell_volume(c), 0.0);
}

TEST(Reorder, CellsFollowTheirNodesAndFacesTheirCells) {
    Mesh m = shuffled_grid();
    const Mesh before = m;
    const std::vector<Index> order = rcm_node_order(m);
    renumber_nodes(m, order);
    // a node keeps its position under its new number
    for (std::size_t i = 0; i < before.rest.size(); ++i)
        EXPECT_EQ(m.rest[std::size_t(order[i])], before.rest[i]);
    sort_cells_by_nodes(m);
    EXPECT_NO_THROW(validate(m));
    Index last = -1;
    for (const Cell& c : m.cells) {
        const Index lo = *std::min_element(c.nodes.begin(), c.nodes.end());
        EXPECT_GE(lo, last);
        last = lo;
    }
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        const Face& face = m.faces[f];
        const auto& owner = m.cells[std::size_t(face.owner)].faces;
        EXPECT_NE(std::find(owner.begin(), owner.end(), Index(f)), owner.end());
        if (face.neighbour != kNone) {
            const auto& other = m.cells[std::size_t(face.neighbour)].faces;
            EXPECT_NE(std::find(other.begin(), other.end(), Index(f)), other.end());
        }
    }
}

TEST(Reorder, RejectsANonPermutation) {
    Mesh m = shuffled_grid();
    std::vector<Index> bad(m.rest.size(), 0);
    EXPECT_THROW(renumber_nodes(m, bad), InputError);
    EXPECT_THROW(renumber_nodes(m, std::vector<Index>(3, 0)), InputError);
}
