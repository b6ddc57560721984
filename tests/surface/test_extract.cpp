#include "polycut/mesh/builders.hpp"
#include "polycut/surface/extract.hpp"

#include <gtest/gtest.h>

using namespace polycut;

TEST(Surface, BoxGridBoundaryIsClosedWithExactArea) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.2, 0.1, 0.05);
    g.cells = { 4, 2, 2 };
    for (bool tets : { false, true }) {
        const mesh::Mesh m = tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
        const auto topo = surface::extract_topology(m);
        EXPECT_TRUE(surface::is_closed_oriented(topo));
        // Euler characteristic of a sphere: V - E + F = 2, with E = 3F/2.
        const long V = long(topo.vertex_nodes.size());
        const long F = long(topo.tags.size());
        EXPECT_EQ(V - 3 * F / 2 + F, 2);
        // Outward orientation: the divergence theorem gives the enclosed volume.
        std::vector<float> pos;
        surface::gather_positions(topo, m.rest, pos);
        double vol = 0;
        for (std::size_t t = 0; t < topo.triangles.size(); t += 3) {
            Vec3 p[3];
            for (int k = 0; k < 3; ++k) {
                const auto v = topo.triangles[t + std::size_t(k)];
                p[k] = Vec3(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
            }
            vol += p[0].dot(p[1].cross(p[2])) / 6.0;
        }
        EXPECT_NEAR(vol, 0.2 * 0.1 * 0.05, 1e-9);
    }
}

TEST(Surface, RemovingATriangleOpensTheSurface) {
    mesh::BoxGrid g;
    g.cells = { 1, 1, 1 };
    auto topo = surface::extract_topology(mesh::hex_grid(g));
    EXPECT_EQ(topo.tags.size(), 12u);
    topo.triangles.resize(topo.triangles.size() - 3);
    EXPECT_FALSE(surface::is_closed_oriented(topo));
}
