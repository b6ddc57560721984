// Shading normals: exact normals on planar and box surfaces, splits at creases and tag
// boundaries, area weighting, and validation of the plain input arrays.
#include "polycut/common/error.hpp"
#include "polycut/render/shaded_mesh.hpp"
#include "scenes.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <thread>

namespace polycut::render::test {
namespace {

/// n x n quads in the plane z = 0, two triangles each, counter-clockwise seen from +z.
TestSurface plane_grid(int n, std::uint8_t tag_left, std::uint8_t tag_right) {
    TestSurface s;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            s.positions.insert(s.positions.end(), { float(i), float(j), 0.0f });
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            s.triangles.insert(s.triangles.end(), { a, b, c, a, c, d });
            s.tags.insert(s.tags.end(), 2, 2 * i < n ? tag_left : tag_right);
        }
    return s;
}

/// The unit cube as 8 shared vertices and 12 outward triangles.
TestSurface cube() {
    TestSurface s;
    for (int v = 0; v < 8; ++v)
        s.positions.insert(s.positions.end(), { float(v & 1), float((v >> 1) & 1), float(v >> 2) });
    s.triangles = { 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6,
        0, 6, 2, 1, 3, 7, 1, 7, 5 };
    s.tags.assign(12, 1);
    return s;
}

TEST(ShadedMesh, PlaneIsOneSmoothGroupWithExactNormal) {
    const TestSurface s = plane_grid(4, 1, 1);
    ShadedMesh mesh;
    build_shaded_mesh(s.arrays(), 180, mesh);
    ASSERT_EQ(mesh.source.size(), 25u); // no vertex split
    for (std::size_t r = 0; r < mesh.source.size(); ++r) {
        EXPECT_FLOAT_EQ(mesh.normals[3 * r + 2], 1.0f);
        EXPECT_FLOAT_EQ(mesh.positions[3 * r], s.positions[3 * mesh.source[r]]);
    }
}

TEST(ShadedMesh, TagBoundarySplitsVertices) {
    // Left half skin, right half cut: the 5 vertices on the line x = 2 are duplicated.
    const TestSurface s = plane_grid(4, 1, 2);
    ShadedMesh mesh;
    build_shaded_mesh(s.arrays(), 180, mesh);
    EXPECT_EQ(mesh.source.size(), 30u);
    // Every render triangle references vertices of its own tag at the same positions.
    for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
        EXPECT_EQ(mesh.tags[mesh.triangles[c]], s.tags[c / 3]);
        EXPECT_EQ(mesh.source[mesh.triangles[c]], s.triangles[c]);
    }
}

TEST(ShadedMesh, CubeCreasesGiveFaceNormals) {
    ShadedMesh mesh;
    build_shaded_mesh(cube().arrays(), 35, mesh);
    ASSERT_EQ(mesh.source.size(), 24u); // 3 per corner
    for (std::size_t r = 0; r < 24; ++r) {
        const float* n = &mesh.normals[3 * r];
        // Exactly one axis component of magnitude 1.
        EXPECT_FLOAT_EQ(std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]), 1.0f);
        // Outward: the normal points away from the cube centre.
        const float* p = &mesh.positions[3 * r];
        EXPECT_GT(n[0] * (p[0] - 0.5f) + n[1] * (p[1] - 0.5f) + n[2] * (p[2] - 0.5f), 0.0f);
    }
}

TEST(ShadedMesh, SmoothCubeAveragesByArea) {
    ShadedMesh mesh;
    build_shaded_mesh(cube().arrays(), 180, mesh);
    ASSERT_EQ(mesh.source.size(), 8u);
    // Vertex 0 is in two triangles of each of the faces -x, -y, -z: normal -(1, 1, 1)/sqrt3.
    // Vertex 1 is in two triangles of +x and one each of -y, -z (all of area 1/2):
    // the area-weighted normal is (2, -1, -1) / sqrt 6, not the corner diagonal.
    ASSERT_EQ(mesh.source[0], 0u);
    ASSERT_EQ(mesh.source[1], 1u);
    const float s3 = 1 / std::sqrt(3.0f), s6 = 1 / std::sqrt(6.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(mesh.normals[c], -s3, 1e-6);
    EXPECT_NEAR(mesh.normals[3], 2 * s6, 1e-6);
    EXPECT_NEAR(mesh.normals[4], -s6, 1e-6);
    EXPECT_NEAR(mesh.normals[5], -s6, 1e-6);
}

TEST(ShadedMesh, FlatShadingSplitsEveryNonCoplanarEdge) {
    // A tetrahedron: no two faces are coplanar, so crease 0 gives 3 vertices per face.
    TestSurface s;
    s.positions = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    s.triangles = { 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3 };
    s.tags.assign(4, 1);
    ShadedMesh mesh;
    build_shaded_mesh(s.arrays(), 0, mesh);
    EXPECT_EQ(mesh.source.size(), 12u);
    build_shaded_mesh(s.arrays(), 180, mesh);
    EXPECT_EQ(mesh.source.size(), 4u);
}

/// build_shaded_mesh on a thread of its own, i.e. with an empty topology cache.
ShadedMesh fresh_build(const TestSurface& s, double crease_angle_deg) {
    ShadedMesh mesh;
    std::thread([&] { build_shaded_mesh(s.arrays(), crease_angle_deg, mesh); }).join();
    return mesh;
}

void expect_identical(const ShadedMesh& a, const ShadedMesh& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals); // bit-identical, not merely close
    EXPECT_EQ(a.tags, b.tags);
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(ShadedMesh, CachedTopologyGivesTheSameMeshAsAFreshBuild) {
    // Frames of one topology reuse the incidence and grouping; the result must equal a build
    // from scratch bit for bit, also when a deformation opens or closes a crease (which changes
    // the grouping) and when the tags or triangles change.
    TestSurface s = plane_grid(6, 1, 2);
    ShadedMesh mesh;
    build_shaded_mesh(s.arrays(), 35, mesh);
    expect_identical(mesh, fresh_build(s, 35));
    for (int frame = 1; frame <= 4; ++frame) {
        // Fold the grid about x = 2 by an angle that crosses the 35 degree crease at frame 3.
        const float angle = 0.25f * float(frame); // 14, 29, 43, 57 degrees
        for (std::size_t v = 0; v < s.positions.size() / 3; ++v) {
            const float x = float(v % 7);
            if (x > 2) {
                s.positions[3 * v] = 2 + (x - 2) * std::cos(angle);
                s.positions[3 * v + 2] = (x - 2) * std::sin(angle);
            }
        }
        build_shaded_mesh(s.arrays(), 35, mesh);
        const ShadedMesh fresh = fresh_build(s, 35);
        expect_identical(mesh, fresh);
        // Below the crease angle the fold is smooth (no split at x = 2), above it splits.
        const std::size_t smooth_count = fresh_build(plane_grid(6, 1, 2), 35).source.size();
        if (angle < 0.61f) // 35 degrees
            EXPECT_EQ(mesh.source.size(), smooth_count) << "frame " << frame;
        else
            EXPECT_GT(mesh.source.size(), smooth_count) << "frame " << frame;
    }
    s.tags.assign(s.tags.size(), 1); // new tags, same triangles: the cache must notice
    build_shaded_mesh(s.arrays(), 35, mesh);
    expect_identical(mesh, fresh_build(s, 35));
    std::swap(s.triangles[0], s.triangles[1]); // flipped triangle, same sizes
    build_shaded_mesh(s.arrays(), 35, mesh);
    expect_identical(mesh, fresh_build(s, 35));
}

TEST(ShadedMesh, DegenerateTriangleGetsAUnitNormal) {
    TestSurface s;
    s.positions = { 0, 0, 0, 1, 0, 0, 2, 0, 0 }; // collinear
    s.triangles = { 0, 1, 2 };
    ShadedMesh mesh;
    build_shaded_mesh(s.arrays(), 35, mesh);
    for (std::size_t r = 0; r < mesh.source.size(); ++r) {
        const float* n = &mesh.normals[3 * r];
        EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0f, 1e-6);
    }
}

TEST(ShadedMesh, ValidateNamesTheBadEntry) {
    TestSurface s = plane_grid(2, 1, 1);
    EXPECT_NO_THROW(s.arrays().validate());

    TestSurface bad_index = s;
    bad_index.triangles[7] = 9; // only 9 vertices
    try {
        bad_index.arrays().validate();
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.where(), "/surface/triangles/2");
    }

    TestSurface nan = s;
    nan.positions[13] = std::nanf("");
    try {
        nan.arrays().validate();
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.where(), "/surface/positions/4");
    }

    TestSurface bad_tag = s;
    bad_tag.tags[3] = 7;
    EXPECT_THROW(bad_tag.arrays().validate(), InputError);

    TestSurface short_tags = s;
    short_tags.tags.pop_back();
    EXPECT_THROW(short_tags.arrays().validate(), InputError);

    TestSurface ragged = s;
    ragged.positions.pop_back();
    EXPECT_THROW(ragged.arrays().validate(), InputError);
}

} // namespace
} // namespace polycut::render::test
