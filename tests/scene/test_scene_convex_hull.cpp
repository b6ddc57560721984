// The "convex_hull" scene geometry: parsing (points or a named shape, never both) and the one
// convex cell build_mesh makes of it, with errors pointing at the offending point.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/build_mesh.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

using namespace polycut;
using namespace polycut::scene;

namespace {
std::string scene_with(const std::string& geometry) {
    return R"({"name": "hull", "method": "mvc", "geometry": )" + geometry
        + R"(, "material": {"youngs_modulus": 1e4}})";
}

const char* kCube = R"({"type": "convex_hull", "points": [[0, 0, 0], [1, 0, 0], [1, 1, 0],
    [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], "scale": 0.1})";

/// JSON pointer of the SceneError that parsing or building throws ("" if none).
std::string error_pointer(const std::string& geometry) {
    try {
        sim::build_mesh(parse_scene(scene_with(geometry)));
    } catch (const SceneError& e) {
        return e.where();
    }
    return "";
}

std::string cube_with(const std::string& extra_point) {
    std::string g = kCube;
    return g.replace(g.find("[0, 0, 0]"), 9, extra_point + ", [0, 0, 0]");
}
} // namespace

TEST(SceneConvexHull, PointsMakeOneScaledCell) {
    const Scene s = parse_scene(scene_with(kCube));
    EXPECT_EQ(s.geometry.kind, Geometry::Kind::ConvexHull);
    EXPECT_EQ(s.geometry.points.size(), 8u);
    const mesh::Mesh m = sim::build_mesh(s);
    ASSERT_EQ(m.num_cells(), 1);
    EXPECT_EQ(m.num_faces(), 6);
    EXPECT_NEAR(m.cell_volume(0), 1e-3, 1e-18); // (0.1 m)^3
    EXPECT_DOUBLE_EQ(m.rest[6].x(), 0.1);
}

TEST(SceneConvexHull, TruncatedOctahedronShape) {
    const Scene s = parse_scene(scene_with(
        R"({"type": "convex_hull", "shape": "truncated_octahedron", "size": 0.02,
            "center": [0, 0, 0.05]})"));
    const mesh::Mesh m = sim::build_mesh(s);
    ASSERT_EQ(m.num_cells(), 1);
    EXPECT_EQ(m.cells[0].nodes.size(), 24u);
    EXPECT_EQ(m.num_faces(), 14);
    EXPECT_NEAR(m.cell_volume(0), 8 * std::numbers::sqrt2 * 8e-6, 1e-19);
    double zmin = 1;
    for (const Vec3& X : m.rest)
        zmin = std::min(zmin, X.z());
    EXPECT_NEAR(zmin, 0.05 - std::numbers::sqrt2 * 0.02, 1e-16); // base square at -sqrt(2) a
}

TEST(SceneConvexHull, ErrorsPointAtTheField) {
    EXPECT_EQ(error_pointer(kCube), "");
    EXPECT_EQ(error_pointer(cube_with("[0.5, 0.5, 0.5]")), "/geometry/points/0"); // inside
    EXPECT_EQ(error_pointer(cube_with("[0.5, 0.5, 1]")), "/geometry/points/0"); // on a face
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "points": [[0, 0, 0], [1, 0, 0],
        [0, 1, 0], [1, 1, 0]]})"),
        "/geometry/points"); // flat
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "points": [[0, 0, 0], [1, 0, 0],
        [0, 1, 0]]})"),
        "/geometry/points"); // too few
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "points": [[0, 0, 0], [1, 0, 0],
        [0, 1, 0], [0, 0, "a"]]})"),
        "/geometry/points/3/2");
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "shape": "truncated_octahedron",
        "size": 0.1, "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]})"),
        "/geometry/shape");
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull"})"), "/geometry/points");
    EXPECT_EQ(
        error_pointer(R"({"type": "convex_hull", "shape": "cube", "size": 1})"), "/geometry/shape");
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "shape": "truncated_octahedron"})"),
        "/geometry/size");
    EXPECT_EQ(error_pointer(R"({"type": "convex_hull", "shape": "truncated_octahedron",
        "size": 0.1, "scale": 2})"),
        "/geometry/scale");
}
