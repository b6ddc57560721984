// Sweep-triangle cuts (000 sec. 5.2): separation, crack fronts, pockets, special positions
// (through a node, along an edge, in a face plane, tangent, outside), bad input, repetition.
#include "polycut/common/error.hpp"
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
mesh::Mesh block(int n, double size = 0.1, bool tets = false) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(size);
    g.cells = Eigen::Vector3i(n, n, n);
    return tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
}

cut::CutInvariants expect_ok(const mesh::Mesh& m, double v0, double vtol = 1e-9) {
    cut::InvariantOptions io;
    io.volume_tol = vtol;
    const auto inv = cut::check_cut_invariants(m, v0, io);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    return inv;
}

// Two triangles covering the square of the plane through `o` spanned by u, v (half-size r).
std::vector<cut::Triangle> square(const Vec3& o, const Vec3& u, const Vec3& v, double r) {
    const Vec3 a = o - r * u - r * v, b = o + r * u - r * v, c = o + r * u + r * v,
               d = o - r * u + r * v;
    return { { a, b, c }, { a, c, d } };
}

// Weights of every new node reproduce its rest position and sum to one.
void expect_weights(const mesh::Mesh& m, const cut::CutReport& r) {
    for (const auto& o : r.new_nodes) {
        Vec3 x = Vec3::Zero();
        double sum = 0;
        for (const auto& [n, w] : o.weights) {
            EXPECT_LT(n, r.nodes_before);
            x += w * m.rest[std::size_t(n)];
            sum += w;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);
        EXPECT_LT((x - m.rest[std::size_t(o.node)]).norm(), 1e-12);
        EXPECT_GE(o.parent_cell, 0);
        EXPECT_LT(o.parent_cell, m.num_cells());
    }
}

std::size_t hash_mesh(const mesh::Mesh& m) {
    std::size_t h = m.rest.size() * 1000003u + m.faces.size() * 7919u + m.cells.size();
    for (const Vec3& x : m.rest)
        h = h * 31 + std::hash<double>()(x.x() + 2 * x.y() + 3 * x.z());
    for (const auto& f : m.faces)
        for (Index n : f.nodes)
            h = h * 131 + std::size_t(n);
    return h;
}
} // namespace

TEST(SweepCut, BlockCutInHalves) {
    for (bool tets : { false, true }) {
        auto m = block(4, 0.1, tets);
        const double v0 = m.rest_volume();
        cut::Cutter cutter(m);
        const auto tris = square(Vec3(0.051, 0.05, 0.05), Vec3::UnitY(), Vec3::UnitZ(), 0.2);
        const auto r = cutter.cut(tris);
        const auto inv = expect_ok(m, v0);
        EXPECT_EQ(inv.components, 2);
        EXPECT_EQ(inv.surface_components, 2);
        if (!tets) {
            EXPECT_EQ(r.new_cells.size(), 16u); // one column of 4x4 hexes split
        }
        EXPECT_EQ(r.pockets, 0);
        EXPECT_TRUE(r.pattern_changed);
        expect_weights(m, r);
        // Volume of each side: x < 0.051 holds 51 % of the block.
        double left = 0;
        for (Index c = 0; c < m.num_cells(); ++c)
            if (m.cell_centroid(c).x() < 0.051)
                left += m.cell_volume(c);
        EXPECT_NEAR(left / v0, 0.51, 1e-12);
    }
}

TEST(SweepCut, CutInFacePlaneSeparatesExistingFaces) {
    auto m = block(4);
    const double v0 = m.rest_volume();
    const Index cells0 = m.num_cells();
    cut::Cutter cutter(m);
    const auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.05), Vec3::UnitY(), Vec3::UnitZ(), 0.2));
    const auto inv = expect_ok(m, v0);
    EXPECT_EQ(inv.components, 2);
    EXPECT_EQ(m.num_cells(), cells0); // no split: the grid faces carry the cut
    // 16 grid faces (some split along the square's diagonal), both sides: twice 1 dm^2 of cut.
    double area = 0;
    for (Index f : r.cut_faces)
        area += geometry::polygon_area(geometry::gather(m.rest, m.faces[std::size_t(f)].nodes));
    EXPECT_NEAR(area, 2 * 0.1 * 0.1, 1e-14);
    EXPECT_GE(r.cut_faces.size(), 32u);
}

TEST(SweepCut, CutThroughNodeAndAlongEdge) {
    {
        auto m = block(4);
        const double v0 = m.rest_volume();
        cut::Cutter cutter(m);
        const Vec3 u = Vec3(1, -1, 0).normalized(), v = Vec3(1, 1, -2).normalized();
        cutter.cut(square(Vec3(0.05, 0.05, 0.05), u, v, 0.3)); // through grid nodes
        EXPECT_EQ(expect_ok(m, v0).components, 2);
    }
    {
        auto m = block(4);
        const double v0 = m.rest_volume();
        cut::Cutter cutter(m);
        const Vec3 u = Vec3(1, -1, 0).normalized();
        cutter.cut(square(Vec3(0.05, 0.05, 0.05), u, Vec3::UnitZ(), 0.3)); // along grid edges
        EXPECT_EQ(expect_ok(m, v0).components, 2);
    }
}

TEST(SweepCut, TangentAndOutsideChangeNothing) {
    auto m = block(3);
    const std::size_t h0 = hash_mesh(m);
    cut::Cutter cutter(m);
    // In the top skin plane, touching the block only on its surface.
    auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.1), Vec3::UnitX(), Vec3::UnitY(), 0.03));
    EXPECT_FALSE(r.topology_changed);
    // Touching one corner edge from outside.
    const cut::Triangle corner { Vec3(0.1, 0.1, 0.0), Vec3(0.2, 0.1, 0.0), Vec3(0.1, 0.2, 0.1) };
    r = cutter.cut(std::span(&corner, 1));
    EXPECT_FALSE(r.topology_changed);
    // Far outside.
    r = cutter.cut(square(Vec3(0.5, 0.5, 0.5), Vec3::UnitX(), Vec3::UnitY(), 0.03));
    EXPECT_FALSE(r.topology_changed);
    EXPECT_EQ(r.triangles_missed, 2);
    EXPECT_EQ(hash_mesh(m), h0);
}

TEST(SweepCut, DegenerateTrianglesRejectedWithoutChange) {
    auto m = block(3);
    cut::Cutter cutter(m);
    const std::size_t h0 = hash_mesh(m);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Vec3 a(0.01, 0.02, 0.03), b(0.08, 0.02, 0.05);
    const std::vector<std::vector<cut::Triangle>> bad {
        { { a, b, a } }, // zero area
        { { a, b, 0.5 * (a + b) } }, // collinear
        { { a, b, Vec3(0.05, nan, 0.05) } }, // NaN
        { { a, b, Vec3(1e9, 0, 0) } }, // huge
        { { a, b, Vec3(0.05, 0.09, 0.05) }, { a, b, a } }, // good, then bad: nothing applied
    };
    for (const auto& tris : bad) {
        EXPECT_THROW(cutter.cut(tris), InputError);
        EXPECT_EQ(hash_mesh(m), h0);
    }
}

TEST(SweepCut, InteriorCutOpensWithPocket) {
    auto m = block(2);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    // A small triangle strictly inside one hex: no node inside it, so a pocket node opens it.
    const cut::Triangle t { Vec3(0.02, 0.02, 0.03), Vec3(0.035, 0.02, 0.03),
        Vec3(0.02, 0.035, 0.031) };
    const auto r = cutter.cut(std::span(&t, 1));
    const auto inv = expect_ok(m, v0);
    EXPECT_EQ(r.pockets, 1);
    EXPECT_EQ(inv.components, 1);
    EXPECT_EQ(inv.surface_components, 2); // skin + closed internal crack
    expect_weights(m, r);
}

TEST(SweepCut, ProgressiveIncisionAdvances) {
    // A vertical blade from above the block down to 4 cm deep, moving along y in 2 mm steps
    // (000 Fig. 8): the cut extends, stays one piece, every invariant after each step.
    auto m = block(4);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    auto blade = [](double y) {
        const double x = 0.0507 + 0.002 * std::sin(30 * y); // slightly curved path
        return std::pair<Vec3, Vec3> { Vec3(x, y, 0.12), Vec3(x, y, 0.06) };
    };
    Index max_nodes = 0;
    for (double y = -0.01; y < 0.06; y += 0.002) {
        const auto [a0, b0] = blade(y);
        const auto [a1, b1] = blade(y + 0.002);
        const std::vector<cut::Triangle> tris { { a0, b0, b1 }, { a0, b1, a1 } };
        const auto r = cutter.cut(tris);
        expect_weights(m, r);
        const auto inv = expect_ok(m, v0);
        ASSERT_TRUE(inv.ok());
        EXPECT_EQ(inv.components, 1);
        max_nodes = std::max<Index>(max_nodes, m.num_nodes());
    }
    // The crack reaches y = 0.06 of the 0.1 block: still one piece; compare with the tets a
    // tetrahedral representation of the same cells would need (fan of each cell from its
    // centroid: one tet per boundary triangle of the cell), 000 sec. 6.
    Index tets = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        for (Index f : m.cells[std::size_t(c)].faces)
            tets += Index(m.faces[std::size_t(f)].nodes.size()) - 2;
    std::cout << "progressive incision: " << m.num_cells() << " cells, " << m.num_nodes()
              << " nodes; tetrahedral equivalent " << tets << " tets\n";
    EXPECT_LT(m.num_cells() * 10, tets);
}

TEST(SweepCut, ThinSlices) {
    // 000 Fig. 9-10: slices 1 mm thick off a 10 cm block.
    auto m = block(4);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    for (int k = 1; k <= 5; ++k)
        cutter.cut(square(Vec3(0.001 * k, 0.05, 0.05), Vec3::UnitY(), Vec3::UnitZ(), 0.2));
    const auto inv = expect_ok(m, v0);
    EXPECT_EQ(inv.components, 6);
    double thinnest = 1;
    for (Index c = 0; c < m.num_cells(); ++c)
        if (m.cell_centroid(c).x() < 0.005)
            thinnest = std::min(thinnest, m.cell_volume(c));
    EXPECT_NEAR(thinnest, 0.001 * 0.025 * 0.025, 1e-15);
}

TEST(SweepCut, PencilSharpening) {
    // 003 Fig. 7: one convex cell cut again and again; each cut shaves a chip off (chips stay
    // in rest space, so later planes may slice them again: components only grow).
    auto m = block(1, 0.02);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    Index pieces = 1, cuts = 0;
    for (int k = 0; k < 24; ++k) {
        const double phi = 2 * M_PI * k / 8 + 0.1 * k;
        const Vec3 n(std::cos(phi), std::sin(phi), 0.4);
        const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.normalized().cross(u);
        const double r = 0.0085 - 0.0002 * k; // each round shaves deeper
        const auto rep
            = cutter.cut(square(Vec3(0.01, 0.01, 0.01) + r * n.normalized(), u, v, 0.05));
        cuts += rep.cut_faces.empty() ? 0 : 1;
        const auto inv = expect_ok(m, v0);
        ASSERT_TRUE(inv.ok()) << "cut " << k;
        EXPECT_GE(inv.components, pieces);
        pieces = inv.components;
    }
    EXPECT_GT(cuts, 20);
    // The core (the piece holding the cell centre) is what the last planes left of the cube.
    std::cout << "pencil: " << m.num_cells() << " cells, " << m.num_nodes() << " nodes, " << pieces
              << " pieces after " << cuts << " cuts\n";
}

TEST(SweepCut, RepeatedCutInSamePlaceIsStable) {
    auto m = block(3);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    const cut::Triangle t { Vec3(0.021, -0.01, 0.12), Vec3(0.043, 0.07, 0.12),
        Vec3(0.03, 0.03, 0.04) };
    cutter.cut(std::span(&t, 1));
    const Index cells = m.num_cells(), nodes = m.num_nodes();
    for (int k = 0; k < 100; ++k) {
        cut::Triangle tk = t;
        tk[2].x() += 1e-7 * ((k % 3) - 1); // jitter well below the snapping distance
        const auto r = cutter.cut(std::span(&tk, 1));
        EXPECT_FALSE(r.topology_changed) << k;
    }
    EXPECT_EQ(m.num_cells(), cells);
    EXPECT_EQ(m.num_nodes(), nodes);
    expect_ok(m, v0);
}

TEST(SweepCut, CoarseningKeepsTheGeometryWithFewerNodes) {
    // The progressive incision with and without coarsening behind the crack front: the same
    // volume and boundary area (the faces keep their shape), every invariant, fewer used nodes.
    auto run = [](bool coarsen) {
        auto m = block(4);
        cut::CutOptions opt;
        opt.coarsen = coarsen;
        // Coarsening alone: with merged Cut faces too, fewer later splits are skipped as
        // degenerate and the two runs would cut different areas (test_merge_faces.cpp).
        opt.merge_cut_faces = false;
        cut::Cutter cutter(m, opt);
        Index removed = 0;
        for (double y = -0.01; y < 0.06; y += 0.002) {
            const double x0 = 0.0507 + 0.002 * std::sin(30 * y); // the curved path above
            const double x1 = 0.0507 + 0.002 * std::sin(30 * (y + 0.002));
            const Vec3 a0(x0, y, 0.12), b0(x0, y, 0.06), a1(x1, y + 0.002, 0.12),
                b1(x1, y + 0.002, 0.06);
            const std::vector<cut::Triangle> tris { { a0, b0, b1 }, { a0, b1, a1 } };
            removed += cutter.cut(tris).nodes_coarsened;
        }
        return std::pair { m, removed };
    };
    const auto [fine, none] = run(false);
    const auto [coarse, removed] = run(true);
    EXPECT_EQ(none, 0);
    // 547 -> 534 used nodes (13 coarsened) until the faces of unsplit cells counted as in the
    // plane within the cell-size snapping distance too (sweep_cut.cpp); since, the curved
    // incision takes more faces into its crack as they are and makes fewer nodes to begin
    // with: 526 -> 516 (10).
    EXPECT_GE(removed, 10);
    const double v0 = block(4).rest_volume();
    expect_ok(fine, v0);
    expect_ok(coarse, v0);
    auto used_nodes = [](const mesh::Mesh& m) {
        std::set<Index> used;
        for (const auto& c : m.cells)
            used.insert(c.nodes.begin(), c.nodes.end());
        return used.size();
    };
    auto boundary_area = [](const mesh::Mesh& m) {
        double area = 0;
        for (Index f : m.boundary_faces())
            area += geometry::polygon_area(geometry::gather(m.rest, m.faces[std::size_t(f)].nodes));
        return area;
    };
    EXPECT_LT(used_nodes(coarse), used_nodes(fine));
    std::cout << "cells " << fine.num_cells() << " -> " << coarse.num_cells() << ", used nodes "
              << used_nodes(fine) << " -> " << used_nodes(coarse) << " (" << removed
              << " coarsened)\n";
    EXPECT_NEAR(coarse.rest_volume(), fine.rest_volume(), 1e-12 * v0);
    EXPECT_NEAR(boundary_area(coarse), boundary_area(fine), 1e-9 * boundary_area(fine));
}

TEST(SweepCut, OnlyFacesUnderTheTriangleMoveOntoItsPlane) {
    // Faces in the plane that a triangle's bounds hold but the triangle does not cover stay
    // where they are: moving their nodes onto a plane turned by a hair (the deformation maps
    // each strip of a stroke to a slightly different rest plane) changed every cell at them
    // for nothing the cut keeps (a strip through the pressed organ: 10 cells split, 140 more
    // changed by such moves). The lower half of an 8^3 hex block is split by the plane
    // y = 0.0531 (interior faces in it), then a triangle in that plane turned by 1e-6 rad cuts
    // from above down to the lower half along one diagonal.
    auto m = block(8);
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m);
    const Vec3 n0 = Vec3::UnitY();
    std::vector<Index> lower;
    for (Index c = 0; c < m.num_cells(); ++c) {
        double z = 0;
        for (Index v : m.cells[std::size_t(c)].nodes)
            z += m.rest[std::size_t(v)].z() / double(m.cells[std::size_t(c)].nodes.size());
        if (z < 0.05)
            lower.push_back(c);
    }
    cutter.split_by_plane(Vec3(0, 0.0531, 0), n0, lower);
    expect_ok(m, v0);
    // The triangle: from (0.03, 0.1) and (0.07, 0.1) at the top down to (0.07, 0.02), in the
    // plane through (0.05, 0.0531, 0.06) whose normal is turned by 1e-6 rad about x.
    const Vec3 o(0.05, 0.0531, 0.06);
    const Vec3 n = Vec3(0, std::cos(1e-6), std::sin(1e-6));
    const auto on = [&](double x, double z) {
        Vec3 p(x, 0.0531, z);
        return Vec3(p - (p - o).dot(n) * n);
    };
    const cut::Triangle tri { on(0.03, 0.1), on(0.07, 0.02), on(0.07, 0.1) };
    const auto r = cutter.cut(std::vector<cut::Triangle> { tri });
    expect_ok(m, v0);
    EXPECT_FALSE(r.cut_faces.empty());
    // The nodes the cut moved are nodes of the cells the triangle crosses: none lies beyond its
    // long edge by more than a cell's diagonal in the plane (17.7 mm). With every face in the
    // plane moved, 20 nodes moved instead of 12, some farther than that beyond the edge.
    const Vec3 a = tri[0], b = tri[1];
    const Vec3 out = n.cross(b - a).normalized(); // from the long edge away from the triangle
    ASSERT_GT((tri[2] - a).dot(-out), 0);
    std::size_t beyond = 0;
    for (const auto& [node, old_rest] : r.moved_nodes)
        if ((old_rest - a).dot(out) > std::sqrt(2.0) * 0.0125 * (1 + 1e-9))
            ++beyond;
    EXPECT_EQ(beyond, 0u) << r.moved_nodes.size() << " nodes moved";
}
