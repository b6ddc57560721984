#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::geometry;

namespace {
std::vector<Vec3> cube_points() {
    std::vector<Vec3> p;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                p.emplace_back(2.0 * i, 3.0 * j, 5.0 * k);
    return p;
}
// Outward loops of the box with points indexed i + 2j + 4k.
std::vector<std::vector<Index>> cube_loops() {
    return { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 }, { 0, 4, 6, 2 },
        { 1, 3, 7, 5 } };
}
} // namespace

TEST(Geometry, PolygonAreaNormalCentroid) {
    const std::vector<Vec3> sq { { 0, 0, 1 }, { 2, 0, 1 }, { 2, 2, 1 }, { 0, 2, 1 } };
    EXPECT_NEAR(polygon_area(sq), 4.0, 1e-14);
    EXPECT_NEAR((polygon_normal(sq) - Vec3(0, 0, 1)).norm(), 0.0, 1e-14);
    EXPECT_NEAR((polygon_centroid(sq) - Vec3(1, 1, 1)).norm(), 0.0, 1e-14);
    EXPECT_NEAR(planarity_error(sq), 0.0, 1e-14);
    // An L-shape: area 3, centroid by composite areas.
    const std::vector<Vec3> L { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 },
        { 0, 2, 0 } };
    EXPECT_NEAR(polygon_area(L), 3.0, 1e-14);
    const Vec3 expect = (2.0 * Vec3(1, 0.5, 0) + 1.0 * Vec3(0.5, 1.5, 0)) / 3.0;
    EXPECT_NEAR((polygon_centroid(L) - expect).norm(), 0.0, 1e-14);
}

TEST(Geometry, BoxVolumeCentroidConvexity) {
    const auto p = cube_points();
    const auto loops = cube_loops();
    EXPECT_NEAR(polyhedron_volume(p, loops), 30.0, 1e-12);
    EXPECT_NEAR((polyhedron_centroid(p, loops) - Vec3(1, 1.5, 2.5)).norm(), 0.0, 1e-12);
    EXPECT_TRUE(polyhedron_is_convex(p, loops));
    auto dented = p;
    dented[7] = Vec3(1, 1.5, 2.5); // pull a corner to the centre: no longer convex
    // Faces through node 7 become non-planar, but convexity of the others is violated too.
    EXPECT_FALSE(polyhedron_is_convex(dented, loops));
}

TEST(Geometry, WindingNumberInsideOutsideAndInANotch) {
    const auto p = cube_points();
    const auto loops = cube_loops();
    EXPECT_NEAR(polyhedron_winding(p, loops, Vec3(1, 1.5, 2.5)), 1.0, 1e-12);
    EXPECT_NEAR(polyhedron_winding(p, loops, Vec3(1.9, 0.1, 4.9)), 1.0, 1e-12);
    EXPECT_NEAR(polyhedron_winding(p, loops, Vec3(3, 1.5, 2.5)), 0.0, 1e-12);
    EXPECT_NEAR(polyhedron_winding(p, loops, Vec3(1, 1.5, 2.5 + 1e3)), 0.0, 1e-12);
    EXPECT_NEAR(polyhedron_winding(p, loops, Vec3(1, 1.5, 0)), 0.5, 1e-12); // on a face
    // An L-shaped prism (non-convex): the L of PolygonAreaNormalCentroid extruded by 1.
    std::vector<Vec3> L { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 },
        { 0, 2, 0 } };
    for (int i = 0; i < 6; ++i)
        L.push_back(L[std::size_t(i)] + Vec3(0, 0, 1));
    std::vector<std::vector<Index>> prism { { 5, 4, 3, 2, 1, 0 }, { 6, 7, 8, 9, 10, 11 } };
    for (Index i = 0; i < 6; ++i)
        prism.push_back({ i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6 });
    EXPECT_NEAR(polyhedron_volume(L, prism), 3.0, 1e-12);
    EXPECT_FALSE(polyhedron_is_convex(L, prism));
    EXPECT_NEAR(polyhedron_winding(L, prism, Vec3(0.5, 1.5, 0.5)), 1.0, 1e-12); // in the arm
    EXPECT_NEAR(polyhedron_winding(L, prism, Vec3(1.5, 1.5, 0.5)), 0.0, 1e-12); // the notch
}

TEST(Geometry, AffineFitRecoversRotationAndStretch) {
    const auto X = cube_points();
    const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    Mat3 S;
    S << 1.2, 0.1, 0, 0.1, 0.9, 0.05, 0, 0.05, 1.1;
    const Vec3 t(0.3, -0.2, 4);
    std::vector<Vec3> x;
    for (const Vec3& p : X)
        x.push_back(R * S * p + t);
    const AffineFit fit = fit_affine(X, x);
    ASSERT_TRUE(fit.ok);
    EXPECT_NEAR((fit.A - R * S).norm(), 0.0, 1e-12);
    EXPECT_NEAR((fit.t - t).norm(), 0.0, 1e-12);
    EXPECT_NEAR((polar_rotation(fit.A) - R).norm(), 0.0, 1e-12);
}

TEST(Geometry, PolarRotationOfReflectionIsProper) {
    const Mat3 A = Vec3(1, 1, -0.5).asDiagonal();
    const Mat3 R = polar_rotation(A);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((R.transpose() * R - Mat3::Identity()).norm(), 0.0, 1e-12);
}

TEST(Geometry, AffineFitReportsFlatPointSets) {
    const std::vector<Vec3> flat_pts { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 } };
    EXPECT_FALSE(fit_affine(flat_pts, flat_pts).ok);
}
