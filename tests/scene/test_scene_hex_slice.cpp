// The "hex_slice" scene geometry (003 sec. 10): a surface file or an implicit shape sliced by a
// grid of cubes; parsing, the mesh build_mesh makes of it (volume of the shape), errors
// pointing at the offending field, and mvc refused on the non-convex cells.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/build_mesh.hpp"
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

using namespace polycut;
using namespace polycut::scene;

namespace {
std::string scene_with(const std::string& geometry, const std::string& method = "dg") {
    return R"({"name": "sliced", "method": ")" + method + R"(", "geometry": )" + geometry
        + R"(, "material": {"youngs_modulus": 1e4}})";
}

/// JSON pointer of the SceneError that parsing or building throws ("" if none).
std::string error_pointer(const std::string& geometry, const std::string& method = "dg") {
    try {
        sim::build_mesh(parse_scene(scene_with(geometry, method)));
    } catch (const SceneError& e) {
        return e.where();
    }
    return "";
}
} // namespace

TEST(SceneHexSlice, SphereIsSlicedIntoHexesAndCutCells) {
    const Scene s = parse_scene(scene_with(R"({"type": "hex_slice", "surface": {"shape":
        "sphere", "radius": 0.05, "triangle_size": 0.006}, "cell_size": 0.02})"));
    EXPECT_EQ(s.geometry.kind, Geometry::Kind::HexSlice);
    EXPECT_DOUBLE_EQ(s.geometry.merge_fraction, 0.1); // the default
    sim::MeshingSummary summary;
    const mesh::Mesh m = sim::build_mesh(s, &summary);
    EXPECT_EQ(summary.source, "hex_slice");
    Index hexes = 0;
    for (const auto& c : m.cells)
        hexes += c.shape == mesh::CellShape::Hex;
    EXPECT_GT(hexes, 0);
    EXPECT_GT(m.num_cells(), hexes);
    // The inscribed triangle surface of a 5 cm sphere at 6 mm triangles: within 3 % of the
    // sphere's volume (the exact equality with the surface's volume is HexSlice.* in meshing).
    const double sphere = 4.0 / 3.0 * std::numbers::pi * std::pow(0.05, 3);
    EXPECT_NEAR(m.rest_volume() / sphere, 1.0, 0.03);
}

TEST(SceneHexSlice, BadFieldsAndMvcOnNonConvexCellsAreRefused) {
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "cell_size": 0.02})"), "/geometry/surface");
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": 3, "cell_size": 0.02})"),
        "/geometry/surface");
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": {"shape": "cube"},
        "cell_size": 0.02})"),
        "/geometry/surface/shape");
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": {"shape": "sphere",
        "radius": 0.05}})"),
        "/geometry/cell_size");
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": {"shape": "sphere",
        "radius": 0.05}, "cell_size": 0.02, "merge_fraction": 1.5})"),
        "/geometry/merge_fraction");
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": {"shape": "sphere",
        "radius": 0.05, "depth": 2}, "cell_size": 0.02})"),
        "/geometry/surface/depth");
    try {
        sim::build_mesh(parse_scene(scene_with(
            R"({"type": "hex_slice", "surface": "no_such_file.off", "cell_size": 0.02})")));
        ADD_FAILURE() << "a missing surface file was accepted";
    } catch (const FileError& e) {
        EXPECT_NE(e.path().find("no_such_file.off"), std::string::npos);
    }
    // Mean value coordinates need convex cells (000 sec. 3): refused, naming the method.
    EXPECT_EQ(error_pointer(R"({"type": "hex_slice", "surface": {"shape": "blob",
        "triangle_size": 0.004}, "cell_size": 0.015})",
                  "mvc"),
        "/method");
}
