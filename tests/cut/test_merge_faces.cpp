// Merging coplanar Cut faces of a cell after each cut call (merge_faces.cpp): the strips of a
// progressive cut in one plane become one face per cell and side, their corners are coarsened
// away, and volume, boundary area and every invariant stay as without merging; faces of a bent
// stroke (two planes) are never merged.
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/mesh/builders.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <iostream>
#include <set>

using namespace polycut;

namespace {
mesh::Mesh block(int n) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    return mesh::hex_grid(g);
}

void expect_ok(const mesh::Mesh& m, double v0) {
    cut::InvariantOptions io;
    io.volume_tol = 1e-12;
    io.planarity_tol = 1e-12; // merged faces must stay planar to round-off
    const auto inv = cut::check_cut_invariants(m, v0, io);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
}

// Two triangles covering the strip s in [s0, s1], z in [z0, z1] of the vertical plane through
// `o` with in-plane horizontal direction d.
std::vector<cut::Triangle> strip(
    const Vec3& o, const Vec3& d, double s0, double s1, double z0, double z1) {
    const Vec3 a = o + s0 * d + z0 * Vec3::UnitZ(), b = o + s1 * d + z0 * Vec3::UnitZ(),
               c = o + s1 * d + z1 * Vec3::UnitZ(), e = o + s0 * d + z1 * Vec3::UnitZ();
    return { { a, b, c }, { a, c, e } };
}

std::size_t used_nodes(const mesh::Mesh& m) {
    std::set<Index> used;
    for (const auto& c : m.cells)
        used.insert(c.nodes.begin(), c.nodes.end());
    return used.size();
}

double area(const mesh::Mesh& m, const mesh::Face& f) {
    return geometry::polygon_area(geometry::gather(m.rest, f.nodes));
}

// Boundary area [m^2] and its Cut part.
std::pair<double, double> boundary_area(const mesh::Mesh& m) {
    double all = 0, cut = 0;
    for (Index f : m.boundary_faces()) {
        const auto& face = m.faces[std::size_t(f)];
        all += area(m, face);
        cut += face.tag == mesh::FaceTag::Cut ? area(m, face) : 0.0;
    }
    return { all, cut };
}

// Number of Cut faces of each cell.
std::vector<int> cut_faces_per_cell(const mesh::Mesh& m) {
    std::vector<int> n(m.cells.size(), 0);
    for (std::size_t c = 0; c < m.cells.size(); ++c)
        for (Index f : m.cells[c].faces)
            n[c] += m.faces[std::size_t(f)].tag == mesh::FaceTag::Cut ? 1 : 0;
    return n;
}

const Vec3 kOrigin(0.0507, 0.0, 0.0); // crack plane x = 0.0507 (away from grid nodes)
} // namespace

TEST(MergeCutFaces, TwoCoplanarSweepsOfOneCellLeaveOneCutFacePerSide) {
    // One hex cell; the crack x = 0.0507 advances over y < 0.04, then over 0.04 < y < 0.07 (full
    // height). Each side of the crack ends with one Cut face, the 0.07 x 0.1 rectangle, and the
    // corners of the strips (y = 0.04, where the triangles' diagonals meet the cell's edges)
    // leave the mesh.
    auto run = [](bool merge) {
        auto m = block(1);
        const double v0 = m.rest_volume();
        cut::CutOptions opt;
        opt.merge_cut_faces = merge;
        cut::Cutter cutter(m, opt);
        cutter.cut(strip(kOrigin, Vec3::UnitY(), -0.02, 0.04, -0.02, 0.12));
        expect_ok(m, v0);
        const auto r2 = cutter.cut(strip(kOrigin, Vec3::UnitY(), 0.04, 0.07, -0.02, 0.12));
        expect_ok(m, v0);
        EXPECT_EQ(r2.cells_after, 2);
        EXPECT_EQ(r2.cut_faces_merged, merge ? 4 : 0)
            << "the new strip's two triangles and the old strip, on each side";
        return m;
    };
    const auto plain = run(false);
    const auto merged = run(true);
    for (int n : cut_faces_per_cell(merged))
        EXPECT_EQ(n, 1);
    for (int n : cut_faces_per_cell(plain))
        EXPECT_GE(n, 2);
    for (const auto& f : merged.faces) {
        if (f.tag == mesh::FaceTag::Cut) {
            EXPECT_NEAR(area(merged, f), 0.07 * 0.1, 1e-12 * 0.007);
        }
    }
    // Nothing but the corners of the two boxes: 4 away from the crack per side, the crack
    // plane's corners at y = 0 once per side, those at y = 0.1 and the front pair shared.
    EXPECT_EQ(used_nodes(merged), 8u + 4u + 2u + 2u);
    EXPECT_GT(used_nodes(plain), used_nodes(merged));
    const double v = plain.rest_volume();
    EXPECT_NEAR(merged.rest_volume(), v, 1e-12 * v);
    const auto [a_plain, cut_plain] = boundary_area(plain);
    const auto [a_merged, cut_merged] = boundary_area(merged);
    EXPECT_NEAR(a_merged, a_plain, 1e-12 * a_plain);
    EXPECT_NEAR(cut_merged, 2 * 0.07 * 0.1, 1e-12 * cut_merged);
    EXPECT_EQ(merged.count_components(), 1);
}

TEST(MergeCutFaces, BentPairIsNotMerged) {
    // The crack runs in x = 0.0507 up to y = 0.04, then turns by theta about the line
    // (0.0507, 0.04, z). Faces of the two planes share an edge but must stay apart: every Cut
    // face lies in one of the planes to round-off, both planes keep their full cut area.
    for (const double theta : { 0.01, 0.3 }) {
        SCOPED_TRACE(theta);
        auto m = block(2);
        const double v0 = m.rest_volume();
        cut::Cutter cutter(m);
        cutter.cut(strip(kOrigin, Vec3::UnitY(), -0.02, 0.04, 0.03, 0.12));
        expect_ok(m, v0);
        const Vec3 bend = kOrigin + 0.04 * Vec3::UnitY();
        const Vec3 d(std::sin(theta), std::cos(theta), 0);
        cutter.cut(strip(bend, d, 0.0, 0.03, 0.03, 0.12));
        expect_ok(m, v0);
        const Vec3 n1 = Vec3::UnitX(), n2 = d.cross(Vec3::UnitZ()).normalized();
        double a1 = 0, a2 = 0;
        for (const auto& f : m.faces) {
            if (f.tag != mesh::FaceTag::Cut)
                continue;
            double d1 = 0, d2 = 0;
            for (Index v : f.nodes) {
                d1 = std::max(d1, std::abs((m.rest[std::size_t(v)] - kOrigin).dot(n1)));
                d2 = std::max(d2, std::abs((m.rest[std::size_t(v)] - bend).dot(n2)));
            }
            EXPECT_TRUE(d1 < 1e-15 || d2 < 1e-15) << "a Cut face spans both planes";
            (d1 < 1e-15 ? a1 : a2) += area(m, f);
        }
        // Both sides; plane 1 covers 0 < y < 0.04, plane 2 0 < s < 0.03, both 0.03 < z < 0.1.
        EXPECT_NEAR(a1, 2 * 0.04 * 0.07, 1e-12);
        EXPECT_NEAR(a2, 2 * 0.03 * 0.07, 1e-12);
    }
}

TEST(MergeCutFaces, ProgressiveStraightIncisionKeepsGeometryWithFewerNodes) {
    // A straight incision advancing 4 mm per call through a 4^3 block (as cut_progressive):
    // every cell ends with at most one Cut face, volume and boundary area as without merging,
    // invariants after every call, and fewer used nodes.
    auto run = [](bool merge, Index& merged_faces) {
        auto m = block(4);
        const double v0 = m.rest_volume();
        cut::CutOptions opt;
        opt.merge_cut_faces = merge;
        cut::Cutter cutter(m, opt);
        merged_faces = 0;
        for (double y = -0.01; y < 0.07; y += 0.004) {
            const auto r = cutter.cut(strip(kOrigin, Vec3::UnitY(), y, y + 0.004, 0.04, 0.12));
            merged_faces += r.cut_faces_merged;
            expect_ok(m, v0);
        }
        return m;
    };
    Index none = 0, merged_faces = 0;
    const auto plain = run(false, none);
    const auto merged = run(true, merged_faces);
    EXPECT_EQ(none, 0);
    EXPECT_GT(merged_faces, 20);
    for (int n : cut_faces_per_cell(merged))
        EXPECT_LE(n, 1);
    EXPECT_EQ(merged.num_cells(), plain.num_cells());
    EXPECT_LT(used_nodes(merged), used_nodes(plain));
    std::cout << "cells " << merged.num_cells() << ", used nodes " << used_nodes(plain) << " -> "
              << used_nodes(merged) << ", " << merged_faces << " Cut faces merged\n";
    const double v = plain.rest_volume();
    EXPECT_NEAR(merged.rest_volume(), v, 1e-12 * v);
    const auto [a_plain, cut_plain] = boundary_area(plain);
    const auto [a_merged, cut_merged] = boundary_area(merged);
    EXPECT_NEAR(a_merged, a_plain, 1e-12 * a_plain);
    EXPECT_NEAR(cut_merged, 2 * 0.07 * 0.06, 1e-12);
    EXPECT_EQ(merged.count_components(), plain.count_components());
}
