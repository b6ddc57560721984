// PackedMesh (the undo snapshot's form): unpack(pack(m)) gives m back field by field, for tets,
// merged polyhedra with split-face parents and Cut tags, and an empty mesh; packing again into
// the same arrays (reused buffers) gives the same arrays.
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/packed.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {

void expect_same(const mesh::Mesh& a, const mesh::Mesh& b) {
    ASSERT_EQ(a.rest.size(), b.rest.size());
    for (std::size_t i = 0; i < a.rest.size(); ++i)
        EXPECT_EQ(a.rest[i], b.rest[i]);
    ASSERT_EQ(a.faces.size(), b.faces.size());
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
        EXPECT_EQ(a.faces[f].nodes, b.faces[f].nodes);
        EXPECT_EQ(a.faces[f].owner, b.faces[f].owner);
        EXPECT_EQ(a.faces[f].neighbour, b.faces[f].neighbour);
        EXPECT_EQ(a.faces[f].tag, b.faces[f].tag);
        EXPECT_EQ(a.faces[f].parent, b.faces[f].parent);
    }
    ASSERT_EQ(a.cells.size(), b.cells.size());
    for (std::size_t c = 0; c < a.cells.size(); ++c) {
        EXPECT_EQ(a.cells[c].nodes, b.cells[c].nodes);
        EXPECT_EQ(a.cells[c].faces, b.cells[c].faces);
        EXPECT_EQ(a.cells[c].shape, b.cells[c].shape);
        EXPECT_EQ(a.cells[c].parent, b.cells[c].parent);
    }
}

TEST(PackedMesh, RoundTripsTetsAndPolyhedra) {
    mesh::BoxGrid g;
    g.cells = { 3, 2, 2 };
    mesh::Mesh tets = mesh::tet_grid(g);
    tets.faces[3].tag = mesh::FaceTag::Cut; // fields a cut sets
    tets.faces[5].parent = 2;
    tets.cells[1].parent = 0;
    mesh::PackedMesh p;
    mesh::pack(tets, p);
    expect_same(tets, mesh::unpack(p));

    const mesh::Mesh poly = mesh::merged_hex_grid(g, 0.5, 3);
    mesh::pack(poly, p); // the same buffers, a different mesh
    expect_same(poly, mesh::unpack(p));
    const std::vector<Index> nodes = p.cell_nodes;
    mesh::pack(poly, p);
    EXPECT_EQ(nodes, p.cell_nodes);

    mesh::pack(mesh::Mesh {}, p);
    const mesh::Mesh empty = mesh::unpack(p);
    EXPECT_TRUE(empty.rest.empty() && empty.faces.empty() && empty.cells.empty());
}

} // namespace
