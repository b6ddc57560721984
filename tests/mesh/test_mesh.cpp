#include "polycut/common/error.hpp"
#include "polycut/mesh/mesh.hpp"

#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::mesh;

TEST(Mesh, TwoHexesShareOneFace)
{
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

TEST(Mesh, InvertedTetIsReordered)
{
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    const Mesh m = Mesh::from_tets(X, { { 0, 2, 1, 3 } });
    EXPECT_NEAR(m.cell_volume(0), 1.0 / 6.0, 1e-15);
    EXPECT_EQ(m.cells[0].shape, CellShape::Tet);
}

TEST(Mesh, ThreeCellsOnOneFaceIsAnError)
{
    std::vector<Vec3> X { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, 0, -1 },
        { 1, 1, 1 } };
    EXPECT_THROW(Mesh::from_tets(X, { { 0, 1, 2, 3 }, { 0, 2, 1, 4 }, { 0, 1, 2, 5 } }), MeshError);
    EXPECT_THROW(Mesh::from_tets(X, { { 0, 1, 2, 9 } }), MeshError);
}
