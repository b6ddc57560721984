// Method "dg" on hex-sliced meshes (003 sec. 10, issue 13 item 4): a column whose cut and merged
// cells hold the exact quadratic gravity solution at p = 2, and the shipped
// hex-sliced organ stepping under gravity with its field readable inside non-convex cells.
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/build_mesh.hpp"
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <string>

using namespace polycut;

namespace {

std::string asset(const std::string& name) {
    return std::string(POLYCUT_SOURCE_DIR) + "/assets/scenes/" + name;
}

/// The 2 x 2 x 20 cm box of bar_gravity.json as an OFF surface in the build tree.
std::string column_off() {
    const auto dir = std::filesystem::path(POLYCUT_BINARY_DIR) / "tests" / "sim" / "scratch";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "column.off").string();
    std::ofstream f(path);
    f << "OFF\n8 6 0\n";
    for (int i = 0; i < 8; ++i)
        f << 0.02 * (i & 1) << ' ' << 0.02 * ((i >> 1) & 1) << ' ' << 0.2 * ((i >> 2) & 1) << '\n';
    f << "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
    return path;
}

Index nonconvex_cells(const mesh::Mesh& m) {
    Index n = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        n += !geometry::polyhedron_is_convex(m.rest, m.cell_face_loops(c));
    return n;
}

} // namespace

TEST(DgHexSlice, SlicedColumnHoldsTheExactGravitySolutionAtP2) {
    // bar_gravity.json's column sliced by 7 mm cubes (the grid is offset from the box, so every
    // side is cut; slabs below 30 % of a cube merge into a neighbour, with coplanar faces where
    // they join). Hanging from
    // z = L with nu = 0: u_z(z) = -rho g (L^2 - z^2) / (2 E), quadratic, so DG p = 2 (IP +
    // Nitsche, consistent) reproduces it up to the solver's round-off in every cell.
    scene::Scene s = scene::load_scene(asset("bar_gravity.json"));
    s.geometry = scene::Geometry {};
    s.geometry.kind = scene::Geometry::Kind::HexSlice;
    s.geometry.path = column_off();
    s.geometry.cell_size = 0.007;
    s.geometry.merge_fraction = 0.3;
    s.method = scene::Method::Dg;
    s.basis.degree = 2;
    s.probes.clear();
    const mesh::Mesh m = sim::build_mesh(s);
    Index cut = 0;
    for (const auto& c : m.cells)
        cut += c.shape == mesh::CellShape::Polyhedron;
    EXPECT_GT(cut, 100);
    EXPECT_NEAR(m.rest_volume(), 0.02 * 0.02 * 0.2, 1e-15);
    sim::Simulation sim(s);
    ASSERT_FALSE(sim.step().rolled_back);
    std::vector<Vec3> points;
    for (int k = 0; k <= 20; ++k)
        points.emplace_back(0.003 + 0.0007 * k, 0.017 - 0.0006 * k, 0.0001 + 0.00995 * k);
    std::vector<Vec3> u;
    std::vector<std::uint8_t> inside;
    sim.sample_displacements(points, u, inside);
    const double tip = 1000 * 9.81 * 0.2 * 0.2 / (2 * 1e5);
    double worst = 0;
    for (std::size_t p = 0; p < points.size(); ++p) {
        ASSERT_TRUE(inside[p]) << p;
        const double z = points[p].z();
        const double exact = -1000 * 9.81 * (0.2 * 0.2 - z * z) / (2 * 1e5);
        worst = std::max(worst, std::abs(u[p].z() - exact) / tip);
        EXPECT_NEAR(u[p].x(), 0, 1e-9 * tip);
        EXPECT_NEAR(u[p].y(), 0, 1e-9 * tip);
    }
    std::printf("[ info ] hex-sliced column DG p=2: %ld cells (%ld non-convex), worst error of "
                "u_z %.2e of the tip\n",
        long(m.num_cells()), long(nonconvex_cells(m)), worst);
    EXPECT_LT(worst, 1e-8);
}

TEST(DgHexSlice, ShippedOrganStepsAndIsReadableInsideNonConvexCells) {
    // organ_hex_slice_dg.json: the blob sliced by 10 mm cubes, DG p = 2; 30 ticks at 60 Hz
    // under gravity: no step fails, the surface stays closed, the tip sags, and a sample at the
    // centroid of every cell (inside it for a non-convex cell too) reads a finite field.
    sim::Simulation sim(scene::load_scene(asset("organ_hex_slice_dg.json")));
    const sim::ModelStats st = sim.model_stats();
    EXPECT_GT(st.hexes, 20);
    EXPECT_GT(st.polyhedra, 100);
    EXPECT_EQ(st.dofs, 30 * (st.hexes + st.polyhedra));
    for (int k = 0; k < 30; ++k)
        ASSERT_FALSE(sim.step().rolled_back) << "step " << k;
    EXPECT_LT(sim.probe_displacement("tip").z(), -1e-3);
    EXPECT_TRUE(sim.mesh_stats().surface_closed);
    const mesh::Mesh m = sim::build_mesh(scene::load_scene(asset("organ_hex_slice_dg.json")));
    std::vector<Vec3> points;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto loops = m.cell_face_loops(c);
        const Vec3 x = geometry::polyhedron_centroid(m.rest, loops);
        if (geometry::polyhedron_winding(m.rest, loops, x) > 0.5) // centroid inside its cell
            points.push_back(x);
    }
    std::vector<Vec3> u;
    std::vector<std::uint8_t> inside;
    sim.sample_displacements(points, u, inside);
    Index read = 0;
    for (std::size_t p = 0; p < points.size(); ++p)
        read += inside[p] && u[p].allFinite() && u[p].norm() < 0.05;
    EXPECT_EQ(read, Index(points.size()));
    EXPECT_GT(nonconvex_cells(m), 50);
}
