#include "polycut/common/error.hpp"
#include "polycut/mesh/mesh.hpp"

#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::mesh;

TEST(Mesh, TwoHexesShareOneFace) {
    std::vector<Vec3> X;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i)
                X.emplace_back(i, j, k);
    auto id = [](int i, int j, int k) { return Index(i + 3 * j + 6 * k); };
    std::vector<std::array<Index, 8>> hexes;
    for (int i = 0; i < 2; ++i)
        hexes.push_back({ id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0), id(i, 0, 1),
            id(i + 1, 0, 1), id(i + 1, 1, 1), id(i, 1, 1) });
    const Mesh m = Mesh::from_hexes(X, hexes);
    EXPECT_EQ(m.num_cells(), 2);
    EXPECT_EQ(m.num_faces(), 11);
    EXPECT_EQ(m.boundary_faces().size(), 10u);
    EXPECT_EQ(m.num_boundary_triangles(), 20);
    EXPECT_NEAR(m.rest_volume(), 2.0, 1e-14);
    EXPECT_EQ(m.cells[0].shape, CellShape::Hex);
    EXPECT_EQ(m.count_components(), 1);
    // classify_cell keeps VTK order for an already ordered hex.
    for (int i = 0; i < 8; ++i)
        EXPECT_EQ(m.cells[1].nodes[std::size_t(i)], hexes[1][std::size_t(i)]);
}

TEST(Mesh, InvertedTetIsReordered) {
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    const Mesh m = Mesh::from_tets(X, { { 0, 2, 1, 3 } });
    EXPECT_NEAR(m.cell_volume(0), 1.0 / 6.0, 1e-15);
    EXPECT_EQ(m.cells[0].shape, CellShape::Tet);
}

TEST(Mesh, ThreeCellsOnOneFaceIsAnError) {
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, 0, -1 },
        { 1, 1, 1 } };
    EXPECT_THROW(Mesh::from_tets(X, { { 0, 1, 2, 3 }, { 0, 2, 1, 4 }, { 0, 1, 2, 5 } }), MeshError);
    EXPECT_THROW(Mesh::from_tets(X, { { 0, 1, 2, 9 } }), MeshError);
}

#include "polycut/mesh/builders.hpp"

TEST(Builders, GridsHaveExactVolumeAndConformingFaces) {
    BoxGrid g;
    g.lo = Vec3(0, 0, 0);
    g.hi = Vec3(1.2, 0.2, 0.3);
    g.cells = { 6, 2, 3 };
    const double V = 1.2 * 0.2 * 0.3;
    const Mesh h = hex_grid(g);
    EXPECT_EQ(h.num_cells(), 36);
    EXPECT_EQ(h.num_nodes(), 7 * 3 * 4);
    EXPECT_NEAR(h.rest_volume(), V, 1e-14);
    // Boundary quads: 2 (6*2 + 6*3 + 2*3) = 72.
    EXPECT_EQ(h.boundary_faces().size(), 72u);
    for (TetSplit split : { TetSplit::Kuhn6, TetSplit::Five }) {
        const Mesh t = tet_grid(g, split);
        EXPECT_EQ(t.num_cells(), 36 * (split == TetSplit::Kuhn6 ? 6 : 5));
        EXPECT_NEAR(t.rest_volume(), V, 1e-14);
        // Conforming: each boundary quad becomes exactly 2 boundary triangles.
        EXPECT_EQ(t.boundary_faces().size(), 144u);
        for (Index c = 0; c < t.num_cells(); ++c)
            EXPECT_GT(t.cell_volume(c), 0.0);
    }
}
