// Hexahedral slicing (003 sec. 10): the cells fill exactly the volume the surface encloses,
// every cell is closed with positive volume, the mesh invariants hold, inner cubes stay hexes,
// small pieces are merged, bad input is refused.
#include "polycut/common/error.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/hex_slice.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/surface.hpp"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <string>

using namespace polycut;
using namespace polycut::meshing;

namespace {

const std::string kMeshes = std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/";

/// The boundary of a Mesh_3 tet mesh of the shape (no optimisers: only the surface is used).
SurfaceMesh shape_surface(const ImplicitShape& shape, double size) {
    MeshingOptions o;
    o.cell_size = size;
    o.perturb = false;
    o.exude = false;
    return boundary_surface(mesh_implicit(shape, o));
}

/// The checks every sliced mesh must pass; returns the report.
HexSliceReport check_sliced(const SurfaceMesh& s, double h, double merge = 0.1) {
    HexSliceOptions o;
    o.cell_size = h;
    o.merge_fraction = merge;
    HexSliceReport r;
    const mesh::Mesh m = hex_slice(s, o, &r);
    SCOPED_TRACE(r.summary());
    std::printf("hex_slice h = %g, merge %g: %s\n", h, merge, r.summary().c_str());
    // The exact volume: the refined surface bounds the cells, so the sum of the cells'
    // volumes equals the enclosed volume up to the rounding of the exact intersection points.
    EXPECT_NEAR(r.mesh_volume / enclosed_volume(s), 1.0, 1e-12);
    EXPECT_NEAR(m.rest_volume() / r.surface_volume, 1.0, 1e-12);
    // Invariants of the mesh (face table, closed cells, planar faces, no inverted or zero
    // cells, no duplicate or unused nodes, closed oriented boundary).
    const auto issues = mesh::check_mesh(m);
    for (const auto& is : issues)
        std::printf(
            "issue cell %ld face %ld: %s\n", long(is.cell), long(is.face), is.message.c_str());
    EXPECT_TRUE(issues.empty()) << (issues.empty() ? "" : issues.front().message) << " ("
                                << issues.size() << " issues)";
    EXPECT_TRUE(mesh::check_boundary_surface(m).ok());
    for (Index c = 0; c < m.num_cells(); ++c)
        EXPECT_GT(m.cell_volume(c), 0) << "cell " << c;
    // The boundary is the surface, refined: same area.
    const SurfaceMesh b = boundary_surface(m);
    EXPECT_NEAR(enclosed_volume(b) / enclosed_volume(s), 1.0, 1e-12);
    // Every cell that is a whole cube is a hex of volume h^3.
    Index hexes = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        if (m.cells[std::size_t(c)].shape == mesh::CellShape::Hex) {
            ++hexes;
            EXPECT_NEAR(m.cell_volume(c), h * h * h, 1e-12 * h * h * h);
        }
    EXPECT_EQ(hexes, r.hexes);
    EXPECT_EQ(r.hexes + r.cut_cells, m.num_cells());
    // Sliver merging: no cell below the threshold except small pieces with no neighbour.
    if (merge > 0 && r.small_kept == 0) {
        EXPECT_GE(r.min_cell_volume, merge * h * h * h * (1 - 1e-12));
    }
    return r;
}

} // namespace

TEST(HexSlice, SphereVolumeIsExactAndCellsAreClosed) {
    const SurfaceMesh s = shape_surface(ImplicitShape::sphere(0.05), 0.008);
    const HexSliceReport r = check_sliced(s, 0.02);
    EXPECT_GT(r.hexes, 0);
    EXPECT_GT(r.cut_cells, 0);
    EXPECT_GT(r.sliced_triangles, r.surface_triangles); // the planes refined the surface
}

TEST(HexSlice, NonConvexOrganSurfaceAtTwoSizes) {
    const SurfaceMesh s = read_surface(kMeshes + "liver_blob.off");
    const HexSliceReport coarse = check_sliced(s, 0.02);
    const HexSliceReport fine = check_sliced(s, 0.01);
    EXPECT_GT(fine.hexes, coarse.hexes);
}

TEST(HexSlice, WithoutMergingEveryPieceIsACell) {
    const SurfaceMesh s = read_surface(kMeshes + "liver_blob.off");
    const HexSliceReport kept = check_sliced(s, 0.015, 0.0);
    const HexSliceReport merged = check_sliced(s, 0.015, 0.2);
    EXPECT_EQ(kept.merged, 0);
    EXPECT_EQ(kept.cut_cells, kept.pieces - kept.holed_faces * 0); // no merging at all
    EXPECT_GT(merged.merged, 0);
    EXPECT_LT(merged.cut_cells, kept.cut_cells);
    EXPECT_LT(kept.min_cell_volume, 0.2 * 0.015 * 0.015 * 0.015);
}

TEST(HexSlice, BoxAlignedWithRoundCoordinatesMovesTheGrid) {
    // A cube of 0.1 m whose faces lie on round coordinates; the grid avoids them.
    SurfaceMesh s;
    for (int i = 0; i < 8; ++i)
        s.positions.emplace_back(0.1 * (i & 1), 0.1 * ((i >> 1) & 1), 0.1 * ((i >> 2) & 1));
    const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 },
        { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
    for (const auto& q : quads) {
        s.triangles.push_back({ q[0], q[1], q[2] });
        s.triangles.push_back({ q[0], q[2], q[3] });
    }
    const HexSliceReport r = check_sliced(s, 0.025);
    EXPECT_NEAR(r.surface_volume, 1e-3, 1e-15);
    EXPECT_EQ(r.hexes, 27); // 5 x 5 x 5 grid cubes, the inner 3 x 3 x 3 whole
}

TEST(HexSlice, RefusesOpenSurfacesAndBadSizes) {
    SurfaceMesh open;
    open.positions = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
    open.triangles = { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 } };
    HexSliceOptions o;
    try {
        hex_slice(open, o);
        ADD_FAILURE() << "open surface accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.where(), "surface");
    }
    open.triangles.push_back({ 0, 3, 2 });
    o.cell_size = 0;
    try {
        hex_slice(open, o);
        ADD_FAILURE() << "cell_size 0 accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.where(), "options.cell_size");
    }
    o.cell_size = 0.1;
    o.merge_fraction = 1.5;
    EXPECT_THROW(hex_slice(open, o), InputError);
}

TEST(HexSlice, FaceWithAHoleMergesItsTwoSides) {
    // A flat torus (R = 10 mm, tube 4 mm) whose tube a grid plane cuts, inside one column of
    // cubes: the plane's square holds an annulus, which one polygon face cannot be. A small
    // octahedron 0.1 m away places the grid (h = 60 mm) so that no x or y plane meets the torus.
    SurfaceMesh s;
    const int nu = 24, nv = 12;
    const double R = 0.01, r = 0.004, pi = 3.141592653589793;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
            s.positions.emplace_back((R + r * std::cos(v)) * std::cos(u),
                (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
        }
    auto id = [&](int i, int j) { return Index(((i + nu) % nu) * nv + (j + nv) % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            s.triangles.push_back({ id(i, j), id(i + 1, j), id(i + 1, j + 1) });
            s.triangles.push_back({ id(i, j), id(i + 1, j + 1), id(i, j + 1) });
        }
    const Index o = Index(s.positions.size());
    const Vec3 c(0.1, 0.1, 0);
    for (int a = 0; a < 3; ++a)
        for (int sign : { 1, -1 }) {
            Vec3 p = c;
            p[a] += sign * 0.005;
            s.positions.push_back(p);
        }
    // +x 0, -x 1, +y 2, -y 3, +z 4, -z 5
    const int oct[8][3] = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 },
        { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
    for (const auto& t : oct)
        s.triangles.push_back({ o + t[0], o + t[1], o + t[2] });
    const HexSliceReport rep = check_sliced(s, 0.06);
    EXPECT_GE(rep.holed_faces, 1);
}
