// Convex hull cells (meshing/convex_hull.hpp): exact counts, outward loops and volumes for the
// cube, the truncated octahedron of seed 000 Fig. 1, a pyramid and a random point cloud, and
// every rejected input naming the offending point.
#include "polycut/geometry/polygon.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/convex_hull.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <map>
#include <numbers>
#include <random>

using namespace polycut;
using namespace polycut::meshing;

namespace {
std::vector<Vec3> cube_corners(double lo = 0, double hi = 1) {
    std::vector<Vec3> p;
    for (int k = 0; k < 8; ++k)
        p.emplace_back(k & 1 ? hi : lo, k & 2 ? hi : lo, k & 4 ? hi : lo);
    return p;
}

/// The cube's corners with x inserted at position pos.
std::vector<Vec3> cube_with(std::size_t pos, const Vec3& x) {
    const auto corners = cube_corners();
    std::vector<Vec3> p;
    for (std::size_t i = 0; i <= corners.size(); ++i) {
        if (i == pos)
            p.push_back(x);
        if (i < corners.size())
            p.push_back(corners[i]);
    }
    return p;
}

Vec3 mean(const std::vector<Vec3>& p) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& x : p)
        c += x;
    return c / double(p.size());
}

/// Every loop's Newell normal points away from the centroid of the nodes (outward), every face
/// is planar to 1e-12 of the diameter, and every directed edge appears once with its reverse
/// once (a closed, consistently oriented surface).
void expect_outward_closed(const ConvexPolyhedron& h) {
    const Vec3 c = mean(h.nodes);
    std::map<std::pair<Index, Index>, int> edges;
    for (const auto& loop : h.faces) {
        const auto pts = geometry::gather(h.nodes, loop);
        EXPECT_GT(geometry::newell_vector(pts).dot(geometry::polygon_centroid(pts) - c), 0);
        EXPECT_LE(geometry::planarity_error(pts), 1e-12);
        for (std::size_t k = 0; k < loop.size(); ++k)
            ++edges[{ loop[k], loop[(k + 1) % loop.size()] }];
    }
    for (const auto& [e, count] : edges) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(edges.count({ e.second, e.first }), 1u) << e.first << "-" << e.second;
    }
}

/// The index a ConvexHullError names (or -2 if nothing is thrown).
Index rejected_index(const std::vector<Vec3>& p) {
    try {
        convex_hull(p);
    } catch (const ConvexHullError& e) {
        return e.index();
    }
    return -2;
}

std::string rejection(const std::vector<Vec3>& p) {
    try {
        convex_hull(p);
    } catch (const ConvexHullError& e) {
        return std::string(e.where()) + ": " + e.problem();
    }
    return "";
}
} // namespace

TEST(ConvexHull, CubeHasEightNodesSixQuadsAndUnitVolume) {
    const auto p = cube_corners();
    const ConvexPolyhedron h = convex_hull(p);
    ASSERT_EQ(h.nodes.size(), 8u);
    EXPECT_EQ(h.nodes, p); // nodes keep the input order
    ASSERT_EQ(h.faces.size(), 6u);
    for (const auto& f : h.faces)
        EXPECT_EQ(f.size(), 4u);
    expect_outward_closed(h);
    const mesh::Mesh m = convex_hull_cell(p);
    ASSERT_EQ(m.num_cells(), 1);
    EXPECT_EQ(m.cells[0].shape, mesh::CellShape::Hex); // recognised: Q1 under every method
    EXPECT_EQ(m.num_faces(), 6);
    EXPECT_DOUBLE_EQ(m.cell_volume(0), 1.0); // exact for unit coordinates
    EXPECT_TRUE(mesh::check_mesh(m).empty());
}

TEST(ConvexHull, TruncatedOctahedronHas14FacesAndVolume8Sqrt2EdgeCubed) {
    const double a = 0.03; // edge length [m]
    const Vec3 centre(0.1, -0.2, 0.3);
    const auto p = truncated_octahedron_points(a, centre);
    ASSERT_EQ(p.size(), 24u);
    for (const Vec3& x : p) // circumradius sqrt(5/2) a
        EXPECT_NEAR((x - centre).norm(), std::sqrt(2.5) * a, 1e-15);
    const ConvexPolyhedron h = convex_hull(p);
    ASSERT_EQ(h.nodes.size(), 24u);
    ASSERT_EQ(h.faces.size(), 14u);
    int squares = 0, hexagons = 0;
    for (const auto& f : h.faces) {
        squares += f.size() == 4;
        hexagons += f.size() == 6;
        for (std::size_t k = 0; k < f.size(); ++k) // every edge has length a
            EXPECT_NEAR(
                (h.nodes[std::size_t(f[k])] - h.nodes[std::size_t(f[(k + 1) % f.size()])]).norm(),
                a, 1e-15);
    }
    EXPECT_EQ(squares, 6);
    EXPECT_EQ(hexagons, 8);
    expect_outward_closed(h);
    const mesh::Mesh m = convex_hull_cell(p);
    EXPECT_EQ(m.cells[0].nodes.size(), 24u);
    EXPECT_EQ(m.cells[0].shape, mesh::CellShape::Polyhedron);
    // Round-off only; the divergence sum about the origin, 0.37 m from the 3 cm cell, cancels
    // about two digits (measured 2.8e-19 m^3 = 9e-16 relative).
    EXPECT_NEAR(m.cell_volume(0), 8 * std::numbers::sqrt2 * a * a * a, 1e-12 * a * a * a);
    EXPECT_TRUE(mesh::check_mesh(m).empty());
}

TEST(ConvexHull, PyramidTetAndRotatedCube) {
    // square pyramid: 1 quad + 4 triangles, volume base * height / 3
    const ConvexPolyhedron pyr = convex_hull(
        { Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0), Vec3(1, 1, 3) });
    EXPECT_EQ(pyr.faces.size(), 5u);
    expect_outward_closed(pyr);
    const mesh::Mesh mp = mesh::Mesh::from_polyhedra(pyr.nodes, { pyr.faces });
    EXPECT_NEAR(mp.cell_volume(0), 4.0, 1e-14);

    const mesh::Mesh tet
        = convex_hull_cell({ Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0) });
    EXPECT_EQ(tet.cells[0].shape, mesh::CellShape::Tet);
    EXPECT_NEAR(tet.cell_volume(0), 1.0 / 6, 1e-15);

    // A rotated cube is not exactly coplanar in doubles: faces within 1e-10 of the diameter of
    // a plane still merge into six quads.
    const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    std::vector<Vec3> rotated;
    for (const Vec3& x : cube_corners(-0.05, 0.05))
        rotated.push_back(R * x + Vec3(0.01, 0.02, 0.03));
    const ConvexPolyhedron rc = convex_hull(rotated);
    EXPECT_EQ(rc.faces.size(), 6u);
    EXPECT_NEAR(convex_hull_cell(rotated).cell_volume(0), 1e-3, 1e-15);
}

TEST(ConvexHull, RandomPointsOnASphereAreAllCorners) {
    std::mt19937 rng(3);
    std::normal_distribution<double> normal;
    std::vector<Vec3> p;
    for (int i = 0; i < 40; ++i)
        p.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized() * 0.1);
    const ConvexPolyhedron h = convex_hull(p);
    EXPECT_EQ(h.nodes.size(), 40u);
    expect_outward_closed(h);
    std::size_t edges = 0;
    for (const auto& f : h.faces)
        edges += f.size();
    EXPECT_EQ(40 - long(edges / 2) + long(h.faces.size()), 2); // Euler characteristic
    const mesh::Mesh m = convex_hull_cell(p);
    EXPECT_GT(m.cell_volume(0), 0);
    EXPECT_LT(m.cell_volume(0), 4.0 / 3 * std::numbers::pi * 1e-3);
}

TEST(ConvexHull, PointsThatAreNotCornersAreRejectedByIndex) {
    const auto inside = cube_with(3, Vec3(0.5, 0.5, 0.5));
    EXPECT_EQ(rejected_index(inside), 3);
    EXPECT_NE(rejection(inside).find("points/3: "), std::string::npos) << rejection(inside);
    EXPECT_NE(rejection(inside).find("must be a corner"), std::string::npos) << rejection(inside);

    const auto on_face = cube_with(8, Vec3(0.25, 0.5, 1)); // inside the top square
    EXPECT_EQ(rejected_index(on_face), 8);

    const auto on_edge = cube_with(0, Vec3(0.5, 0, 0)); // on the bottom front edge
    EXPECT_EQ(rejected_index(on_edge), 0);
    EXPECT_NE(rejection(on_edge).find("not a corner"), std::string::npos) << rejection(on_edge);

    // 1e-13 outside the edge: a corner of the exact hull, but within 1e-10 of the diameter of
    // the edge, so its faces merge and it is reported as lying on the edge
    const auto near_edge = cube_with(2, Vec3(0.5, -1e-13, -1e-13));
    EXPECT_EQ(rejected_index(near_edge), 2);
    EXPECT_NE(rejection(near_edge).find("on an edge"), std::string::npos) << rejection(near_edge);

    const auto repeated = cube_with(8, Vec3(1, 0, 1)); // corner 5 again
    EXPECT_EQ(rejected_index(repeated), 8);
}

TEST(ConvexHull, TooFewFlatAndNonFiniteSetsAreRejected) {
    EXPECT_EQ(rejected_index({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0) }), kNone);
    EXPECT_EQ(rejected_index({}), kNone);
    const std::vector<Vec3> flat
        = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.3, 0.6, 0) };
    EXPECT_EQ(rejected_index(flat), kNone);
    EXPECT_NE(rejection(flat).find("one plane"), std::string::npos) << rejection(flat);
    EXPECT_EQ(rejected_index({ Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3) }),
        kNone); // collinear
    // flat to 1e-13 of the diameter: no volume either
    EXPECT_EQ(
        rejected_index({ Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1e-13) }), kNone);
    auto nan = cube_corners();
    nan[2].y() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(rejected_index(nan), 2);
    auto inf = cube_corners();
    inf[6].z() = std::numeric_limits<double>::infinity();
    EXPECT_EQ(rejected_index(inf), 6);
    EXPECT_THROW(truncated_octahedron_points(0), InputError);
    EXPECT_THROW(truncated_octahedron_points(std::nan("")), InputError);
}
