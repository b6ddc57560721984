// Surface files and surface meshing: OFF/OBJ/STL reading and writing, rejection of malformed
// files with FileError, the boundary of a volume mesh, and CGAL Mesh_3 of closed surfaces
// (round trip through a written OFF file, sharp cube, shipped organ surface).
#include "polycut/common/error.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/surface.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <numbers>
#include <string>

using namespace polycut;
using namespace polycut::meshing;

namespace {

const std::string kData = std::string(POLYCUT_SOURCE_DIR) + "/tests/meshing/data/";

/// A fresh scratch directory for this test executable.
std::filesystem::path scratch() {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::path(POLYCUT_BINARY_DIR) / "tests" / "meshing" / "scratch";
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

std::string write_text(const std::string& name, const std::string& text) {
    const std::string path = (scratch() / name).string();
    std::ofstream(path) << text;
    return path;
}

/// Expects read_surface(path) to throw a FileError naming the path whose problem contains
/// `what`.
void expect_rejected(const std::string& path, const std::string& what, bool closed = true) {
    try {
        read_surface(path, closed);
        ADD_FAILURE() << path << " was accepted";
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(e.problem().find(what), std::string::npos) << e.problem();
    }
}

double surface_area(const SurfaceMesh& s) {
    double area = 0;
    for (const auto& t : s.triangles) {
        const Vec3& a = s.positions[std::size_t(t[0])];
        area += 0.5
            * (s.positions[std::size_t(t[1])] - a).cross(s.positions[std::size_t(t[2])] - a).norm();
    }
    return area;
}

MeshingOptions options(double cell_size) {
    MeshingOptions o;
    o.cell_size = cell_size;
    return o;
}

/// A unit cube as OFF text (quads), optionally without its top face, with a replaceable first
/// vertex line.
std::string cube_off(bool with_top, const std::string& first_vertex = "0 0 0") {
    std::string s = "OFF\n8 " + std::string(with_top ? "6" : "5") + " 0\n" + first_vertex + "\n"
        + "1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        + "4 0 3 2 1\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
    if (with_top)
        s += "4 4 5 6 7\n";
    return s;
}

} // namespace

TEST(ReadSurface, ObjQuadsAreTriangulatedAndOriented) {
    const SurfaceMesh s = read_surface(kData + "cube_quads.obj");
    EXPECT_EQ(s.positions.size(), 8u);
    EXPECT_EQ(s.triangles.size(), 12u);
    EXPECT_NEAR(enclosed_volume(s), 1.25e-4, 1e-18);
    EXPECT_NEAR(surface_area(s), 6 * 0.0025, 1e-16);
}

TEST(ReadSurface, InsideOutSurfaceIsReoriented) {
    // The same cube with every face reversed reads back with a positive enclosed volume.
    std::string text = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                       "4 1 2 3 0\n4 4 5 1 0\n4 5 6 2 1\n4 6 7 3 2\n4 7 4 0 3\n4 7 6 5 4\n";
    const SurfaceMesh s = read_surface(write_text("inside_out.off", text));
    EXPECT_NEAR(enclosed_volume(s), 1.0, 1e-14);
}

TEST(ReadSurface, WriteReadRoundTripInEachFormat) {
    const SurfaceMesh cube = read_surface(kData + "cube_quads.obj");
    for (const char* ext : { ".off", ".obj", ".stl" }) {
        const std::string path = (scratch() / (std::string("cube_roundtrip") + ext)).string();
        write_surface(path, cube);
        const SurfaceMesh back = read_surface(path);
        EXPECT_EQ(back.positions.size(), 8u) << ext; // STL corners are merged again
        EXPECT_EQ(back.triangles.size(), 12u) << ext;
        // OFF and OBJ are written with 17 digits (exact); STL stores single precision.
        const double tol = std::string(ext) == ".stl" ? 1e-6 : 1e-15;
        EXPECT_NEAR(enclosed_volume(back), enclosed_volume(cube), tol * enclosed_volume(cube))
            << ext;
    }
}

TEST(ReadSurface, RejectsMalformedFiles) {
    expect_rejected(kData + "does_not_exist.off", "cannot open");
    expect_rejected(write_text("surface.vtk", "ply\n"), "unsupported");
    expect_rejected(write_text("empty.off", ""), "empty");
    expect_rejected(
        write_text("garbage.off", "this is not an OFF file\n\x01\x02 garbage"), "is not OFF");
    expect_rejected(write_text("garbage.obj", "v 1 2\nf x y z\n"), "");
    expect_rejected(write_text("no_faces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "");
    expect_rejected(write_text("truncated.off", "OFF\n8 6 0\n0 0 0\n1 0 0\n"), "");
    expect_rejected(write_text("bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "");
    expect_rejected(write_text("nan.off", cube_off(true, "nan 0 0")), "not a finite number");
    expect_rejected(write_text("huge.off", cube_off(true, "1e999 0 0")), "");
    expect_rejected(write_text("open.off", cube_off(false)), "not closed");
    // An open surface is fine when a closed one is not required.
    EXPECT_EQ(read_surface((scratch() / "open.off").string(), false).triangles.size(), 10u);
    // Two cubes sharing one edge (vertices 2 and 6): closed, but that edge has four faces.
    std::string two = "OFF\n14 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                      "2 1 0\n2 2 0\n1 2 0\n2 1 1\n2 2 1\n1 2 1\n"
                      "4 0 3 2 1\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n4 4 5 6 7\n"
                      "4 2 10 9 8\n4 2 8 11 6\n4 8 9 12 11\n4 9 10 13 12\n4 10 2 6 13\n"
                      "4 6 11 12 13\n";
    expect_rejected(write_text("nonmanifold.off", two), "manifold");
    // Two overlapping cubes: each closed and manifold, together self-intersecting.
    std::string overlap = "OFF\n16 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                          "0.5 0.5 0.5\n1.5 0.5 0.5\n1.5 1.5 0.5\n0.5 1.5 0.5\n0.5 0.5 1.5\n"
                          "1.5 0.5 1.5\n1.5 1.5 1.5\n0.5 1.5 1.5\n"
                          "4 0 3 2 1\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n4 4 5 6 7\n"
                          "4 8 11 10 9\n4 8 9 13 12\n4 9 10 14 13\n4 10 11 15 14\n"
                          "4 11 8 12 15\n4 12 13 14 15\n";
    expect_rejected(write_text("overlap.off", overlap), "self-intersecting");
}

TEST(BoundarySurface, EnclosesTheMeshVolume) {
    const mesh::Mesh m = mesh_implicit(ImplicitShape::sphere(0.05), options(0.015));
    const SurfaceMesh skin = boundary_surface(m);
    EXPECT_EQ(Index(skin.triangles.size()), m.num_boundary_triangles());
    EXPECT_NEAR(enclosed_volume(skin), m.rest_volume(), 1e-12 * m.rest_volume());
    EXPECT_TRUE(closed_surface_problem(skin).empty()) << closed_surface_problem(skin);
}

// Sphere mesh -> skin -> OFF -> read -> mesh again. The second mesh's boundary vertices lie on
// the first skin and its facets within d of it, so |V2 - V1| <= A d (A = skin area); both are
// within 3 d / r of the ball's volume (inscribed polytopes, see test_implicit.cpp).
TEST(MeshSurface, SphereRoundTripThroughOff) {
    const double r = 0.05;
    MeshingOptions o;
    o.cell_size = 0.01;
    const mesh::Mesh first = mesh_implicit(ImplicitShape::sphere(r), o);
    const SurfaceMesh skin = boundary_surface(first);
    const std::string path = (scratch() / "sphere_skin.off").string();
    write_surface(path, skin);
    const SurfaceMesh back = read_surface(path);
    ASSERT_EQ(back.positions.size(), skin.positions.size());
    ASSERT_EQ(back.triangles.size(), skin.triangles.size());
    for (std::size_t v = 0; v < skin.positions.size(); ++v)
        ASSERT_EQ(back.positions[v], skin.positions[v]) << "vertex " << v; // 17 digits: exact
    const mesh::Mesh second = mesh_surface_file(path, o);
    EXPECT_TRUE(mesh::check_mesh(second).empty());
    for (Index c = 0; c < second.num_cells(); ++c)
        ASSERT_GT(second.cell_volume(c), 0);
    const double d = o.effective_facet_distance();
    const double V1 = first.rest_volume(), V2 = second.rest_volume();
    EXPECT_NEAR(V2, V1, surface_area(skin) * d);
    EXPECT_LE(V2, V1 * (1 + 1e-9)); // convex input: the remesh is inscribed in it
    const double V = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    EXPECT_GE(V2, V * (1 - 2 * 3 * d / r));
    std::printf("[ roundtrip] V_ball %.6e, V1 %.6e (%+.4f), V2 %.6e (%+.4f), %d -> %d nodes\n", V,
        V1, V1 / V - 1, V2, V2 / V - 1, first.num_nodes(), second.num_nodes());
}

// A cube with sharp features: its edges and corners are protected, so the tets fill it exactly
// (all boundary vertices on the flat faces, edges kept straight): volume to round-off.
TEST(MeshSurface, CubeWithSharpFeaturesHasExactVolume) {
    MeshingOptions o;
    o.cell_size = 0.02;
    const mesh::Mesh m = mesh_surface_file(kData + "cube_quads.obj", o);
    EXPECT_TRUE(mesh::check_mesh(m).empty());
    EXPECT_NEAR(m.rest_volume(), 1.25e-4, 1e-9 * 1.25e-4);
    for (const Vec3& x : m.rest) {
        ASSERT_GE(x.minCoeff(), -1e-12);
        ASSERT_LE(x.maxCoeff(), 0.05 + 1e-12);
    }
}

TEST(MeshSurface, ShippedOrganSurface) {
    const std::string path = std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/liver_blob.off";
    const SurfaceMesh s = read_surface(path);
    MeshingOptions o;
    o.cell_size = 0.012;
    const mesh::Mesh m = mesh_surface(s, o);
    EXPECT_TRUE(mesh::check_mesh(m).empty());
    EXPECT_EQ(m.count_components(), 1);
    EXPECT_NEAR(
        m.rest_volume(), enclosed_volume(s), surface_area(s) * o.effective_facet_distance());
}

TEST(MeshSurface, RejectsBadSurfaces) {
    SurfaceMesh nan = read_surface(kData + "cube_quads.obj");
    nan.positions[3].y() = std::nan("");
    EXPECT_NE(closed_surface_problem(nan).find("non-finite"), std::string::npos);
    EXPECT_THROW(mesh_surface(nan, MeshingOptions {}), InputError);

    SurfaceMesh s = read_surface(kData + "cube_quads.obj");
    s.triangles.pop_back();
    EXPECT_THROW(mesh_surface(s, MeshingOptions {}), InputError);
    EXPECT_FALSE(closed_surface_problem(s).empty());
}
