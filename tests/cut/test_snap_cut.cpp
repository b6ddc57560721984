// Face snapping (002 sec. 3.2): halves, progressive incision, special positions (node, edge,
// face plane, tangent, outside), bad input, repetition, quality measures.
#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "test_snap_common.hpp"

#include <cmath>
#include <numbers>
#include <random>

using namespace polycut;
using namespace snaptest;

TEST(SnapQuality, AspectRatioAndDihedralsOfKnownTets) {
    // Regular tet of edge 1: height sqrt(2/3), dihedral angles acos(1/3).
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, std::sqrt(3.0) / 2, 0),
        d(0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3.0));
    EXPECT_NEAR(cut::tet_aspect_ratio(a, b, c, d), std::sqrt(2.0 / 3.0), 1e-12);
    for (double t : cut::tet_dihedral_angles(a, b, c, d))
        EXPECT_NEAR(t, std::acos(1.0 / 3.0), 1e-12);
    // Orthogonal corner tet: three right dihedrals at the corner edges, aspect = h_min / sqrt(2).
    const Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    const auto ang = cut::tet_dihedral_angles(o, x, y, z);
    for (int e = 0; e < 3; ++e)
        EXPECT_NEAR(ang[std::size_t(e)], std::numbers::pi / 2, 1e-12);
    EXPECT_NEAR(cut::tet_aspect_ratio(o, x, y, z), (1 / std::sqrt(3.0)) / std::sqrt(2.0), 1e-12);
    // A cap: apex just above the centroid of the base has three large angles at its edges.
    const Vec3 cap(0.5, std::sqrt(3.0) / 6, 1e-4);
    const auto cang = cut::tet_dihedral_angles(a, b, c, cap);
    int large = 0;
    for (double t : cang)
        large += t > 0.99 * std::numbers::pi ? 1 : 0;
    EXPECT_EQ(large, 3);
    EXPECT_LT(cut::tet_aspect_ratio(a, b, c, cap), 0.01);
    EXPECT_LT(cut::tet_aspect_ratio(b, a, c, d), 0); // inverted
}

TEST(SnapCut, RejectsNonTetMeshes) {
    mesh::BoxGrid g;
    auto hexes = mesh::hex_grid(g);
    EXPECT_THROW(cut::SnapCutter cutter(hexes), InputError);
}

TEST(SnapCut, BlockCutInHalves) {
    auto m = tet_block(6);
    const double v0 = m.rest_volume();
    const Index cells0 = m.num_cells();
    cut::SnapCutter cutter(m);
    const Vec3 n = Vec3(1, 0.2, 0.1).normalized();
    const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.cross(u);
    const auto r = cutter.cut(square(Vec3(0.0513, 0.05, 0.05), u, v, 0.2));
    const auto inv = expect_ok(m, v0);
    EXPECT_EQ(inv.components, 2);
    EXPECT_EQ(inv.surface_components, 2);
    expect_report_consistent(m, r);
    EXPECT_TRUE(r.pattern_changed);
    EXPECT_FALSE(r.cut_faces.empty());
    EXPECT_EQ(cutter.stats().faces_pending, 0);
    // Constant cell count except for degeneracy removal.
    EXPECT_EQ(m.num_cells() + Index(r.removed_cells.size()) - Index(r.new_cells.size()), cells0);
    EXPECT_LT(cutter.stats().volume_change, 1e-3);
    // Snapping puts the cut surface on the sweep plane: every Cut face node within 1e-9 of it,
    // except nodes whose move was refused.
    Index off = 0;
    for (const auto& f : m.faces)
        if (f.tag == mesh::FaceTag::Cut)
            for (Index k : f.nodes)
                off += std::abs(n.dot(m.rest[std::size_t(k)] - Vec3(0.0513, 0.05, 0.05))) > 1e-9;
    EXPECT_LE(off, 3 * cutter.stats().snaps_refused);
    std::cout << "halves: " << r.cut_faces.size() << " cut faces, snapped "
              << cutter.stats().nodes_snapped << ", refused " << cutter.stats().snaps_refused
              << ", degenerate " << cutter.stats().degenerate_found << " collapsed "
              << cutter.stats().edges_collapsed << " left " << cutter.stats().degenerate_left
              << ", volume change " << cutter.stats().volume_change << "\n";
}

TEST(SnapCut, CutInFacePlaneMovesNothing) {
    auto m = tet_block(6);
    const double v0 = m.rest_volume();
    const Index cells0 = m.num_cells();
    cut::SnapCutter cutter(m);
    const auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.05), Vec3::UnitY(), Vec3::UnitZ(), 0.2));
    const auto inv = expect_ok(m, v0, 1e-12);
    EXPECT_EQ(inv.components, 2);
    EXPECT_EQ(m.num_cells(), cells0);
    EXPECT_TRUE(r.moved_nodes.empty());
    // The grid plane x = 0.05 carries the cut: 2 x 6 x 6 squares of two triangles on each side.
    double area = 0;
    for (Index f : r.cut_faces)
        area += geometry::polygon_area(geometry::gather(m.rest, m.faces[std::size_t(f)].nodes));
    EXPECT_NEAR(area, 2 * 0.1 * 0.1, 1e-14);
    EXPECT_EQ(r.cut_faces.size(), 144u);
    EXPECT_EQ(r.duplicated.size(), 49u); // 7 x 7 grid nodes in the plane
}

TEST(SnapCut, CutThroughNodesAndAlongEdges) {
    // Through grid nodes (plane x + y + z = 0.15 hits nodes with i + j + k = 9).
    {
        auto m = tet_block(6);
        const double v0 = m.rest_volume();
        cut::SnapCutter cutter(m);
        const Vec3 u = Vec3(1, -1, 0).normalized(), v = Vec3(1, 1, -2).normalized();
        const auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.05), u, v, 0.3));
        EXPECT_EQ(expect_ok(m, v0).components, 2);
        expect_report_consistent(m, r);
    }
    // Along Kuhn diagonals: the plane x = y holds the main diagonal of every block on it.
    {
        auto m = tet_block(6);
        const double v0 = m.rest_volume();
        cut::SnapCutter cutter(m);
        const Vec3 u = Vec3(1, 1, 0).normalized();
        const auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.05), u, Vec3::UnitZ(), 0.3));
        const auto inv = expect_ok(m, v0, 1e-12);
        EXPECT_EQ(inv.components, 2);
        EXPECT_TRUE(r.moved_nodes.empty()); // every selected face already lies in the plane
    }
}

TEST(SnapCut, TangentAndOutsideChangeNothing) {
    auto m = tet_block(3);
    const std::size_t h0 = hash_mesh(m);
    cut::SnapCutter cutter(m);
    // In the top skin plane.
    auto r = cutter.cut(square(Vec3(0.05, 0.05, 0.1), Vec3::UnitX(), Vec3::UnitY(), 0.2));
    EXPECT_EQ(hash_mesh(m), h0);
    EXPECT_TRUE(r.cut_faces.empty());
    EXPECT_FALSE(r.topology_changed);
    cutter.end_sweep(); // an unrelated sweep: forget the crossings of the first
    // Along a side face, perpendicular to the skin, touching it only along a line.
    r = cutter.cut(square(Vec3(0.05, 0.0, 0.05), Vec3::UnitX(), Vec3::UnitZ(), 0.2));
    EXPECT_EQ(hash_mesh(m), h0);
    cutter.end_sweep();
    // Outside.
    r = cutter.cut(square(Vec3(0.5, 0.5, 0.5), Vec3::UnitX(), Vec3::UnitY(), 0.1));
    EXPECT_EQ(hash_mesh(m), h0);
    EXPECT_EQ(r.triangles_missed, 2);
    EXPECT_FALSE(r.topology_changed);
}

TEST(SnapCut, BadTrianglesThrowAndChangeNothing) {
    auto m = tet_block(3);
    const std::size_t h0 = hash_mesh(m);
    cut::SnapCutter cutter(m);
    const Vec3 p(0.05, 0.05, 0.05);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<std::vector<cut::Triangle>> bad {
        { { p, p, Vec3(p + Vec3::UnitX()) } }, // zero area
        { { p, Vec3(p + Vec3::UnitX()), Vec3(p + 2 * Vec3::UnitX()) } }, // collinear
        { { p, Vec3(nan, 0, 0), Vec3(0, 0, 1) } }, // NaN
        { { p, Vec3(1e9, 0, 0), Vec3(0, 1e9, 0) } }, // huge
        { square(p, Vec3::UnitX(), Vec3::UnitY(), 0.2)[0], { p, p, p } }, // one bad of two
    };
    for (const auto& tris : bad) {
        EXPECT_THROW(cutter.cut(tris), InputError);
        EXPECT_EQ(hash_mesh(m), h0);
    }
}

TEST(SnapCut, ProgressiveIncisionStaysConnected) {
    auto m = tet_block(6);
    const double v0 = m.rest_volume();
    const Index cells0 = m.num_cells();
    cut::SnapCutter cutter(m);
    // A blade spanning the block's height moves in y through a tilted plane, 1 mm per sample:
    // 120 small triangles, one call each (one per tick).
    const Vec3 n = Vec3(1, 0.15, 0.05).normalized();
    const Vec3 t = Vec3::UnitY() - n.y() * n; // in-plane direction of travel
    const Vec3 b0 = Vec3(0.047, -0.005, -0.02), b1 = b0 + 0.14 * n.cross(t).normalized();
    const auto tris = blade_sweep(b0, b1, 1e-3 * t.normalized(), 121);
    Index components = 1, cut_faces = 0, removed = 0, added = 0;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        const auto r = cutter.cut(std::span(&tris[i], 1));
        expect_report_consistent(m, r);
        removed += Index(r.removed_cells.size());
        added += Index(r.new_cells.size());
        cut_faces += Index(r.cut_faces.size());
        const auto inv = expect_ok(m, v0);
        ASSERT_TRUE(inv.ok()) << "after triangle " << i;
        EXPECT_GE(inv.components, components); // never re-attached
        components = inv.components;
    }
    EXPECT_EQ(components, 2); // the blade has crossed the whole block
    EXPECT_EQ(m.num_cells(), cells0 + added - removed);
    EXPECT_GT(cut_faces, 72);
}

TEST(SnapCut, PartialIncisionEndsInside) {
    // A cut entering from the top and ending inside: one component, an open crack.
    auto m = tet_block(6);
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m);
    const Vec3 n = Vec3(1, 0.1, 0.0).normalized();
    const Vec3 u = n.cross(Vec3::UnitZ()).normalized();
    const auto tris = square(Vec3(0.052, 0.05, 0.1), u, Vec3::UnitZ(), 0.05);
    const auto r = cutter.cut(tris);
    const auto inv = expect_ok(m, v0);
    EXPECT_EQ(inv.components, 1);
    EXPECT_FALSE(r.duplicated.empty()); // opened at the top
    EXPECT_EQ(inv.surface_components, 1);
}

TEST(SnapCut, RepeatedCutsAreStable) {
    auto m = tet_block(4);
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m);
    const Vec3 n = Vec3(1, 0.3, 0.2).normalized();
    const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.cross(u);
    const auto tris = square(Vec3(0.049, 0.05, 0.05), u, v, 0.2);
    cutter.cut(tris);
    expect_ok(m, v0);
    const std::size_t h1 = hash_mesh(m);
    // The same sweep again: its crossings are remembered, nothing changes.
    for (int i = 0; i < 100; ++i) {
        const auto r = cutter.cut(tris);
        EXPECT_TRUE(r.new_nodes.empty());
        EXPECT_FALSE(r.topology_changed);
    }
    EXPECT_EQ(hash_mesh(m), h1);
    // As new sweeps (crossings forgotten): the mesh settles after the first repeat and stays.
    std::size_t h2 = 0;
    for (int i = 0; i < 100; ++i) {
        cutter.end_sweep();
        cutter.cut(tris);
        ASSERT_TRUE(expect_ok(m, v0).ok()) << "repeat " << i;
        if (i == 2)
            h2 = hash_mesh(m);
    }
    EXPECT_EQ(hash_mesh(m), h2);
    EXPECT_EQ(expect_ok(m, v0).components, 2);
}

TEST(SnapDegenerate, FlatTetsAreCollapsed) {
    // With a permissive snap guard, snapping flattens tets on an irregular mesh; degeneracy
    // removal (002 sec. 3.2.3) collapses them, keeping every tet positive and the rest volume
    // within 1e-3.
    cut::SnapOptions opt;
    opt.snap_min_aspect = 1e-6;
    opt.degenerate_aspect = 0.05; // stricter than 002's 0.01, so that the cases occur
    Index found = 0, collapsed = 0, left = 0, needles = 0, spindles = 0, slivers = 0, caps = 0;
    std::mt19937 rng(5u);
    Index islands = 0;
    std::uniform_real_distribution<double> J(-0.004, 0.004);
    for (int k = 0; k < 8; ++k) {
        // Interior nodes jittered by up to 0.2 h (002 reports more degeneracies on irregular
        // meshes).
        auto m = tet_block(5);
        for (auto& X : m.rest)
            if ((X.array() > 1e-9).all() && (X.array() < 0.1 - 1e-9).all())
                X += Vec3(J(rng), J(rng), J(rng));
        const double v0 = m.rest_volume();
        cut::SnapCutter cutter(m, opt);
        const Vec3 n = Vec3(1, 0.13 * k, 0.31 - 0.05 * k).normalized();
        const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.cross(u);
        const auto r = cutter.cut(square(Vec3(0.047 + 0.001 * k, 0.05, 0.05), u, v, 0.2));
        expect_report_consistent(m, r);
        const auto inv = expect_ok(m, v0);
        // Two halves: no tet wrapped by the selection comes off as an island
        // (SnapOptions::min_piece_cells).
        EXPECT_EQ(inv.components, 2);
        islands += inv.components - 2;
        const auto& st = cutter.stats();
        found += st.degenerate_found;
        collapsed += st.edges_collapsed;
        left += st.degenerate_left;
        needles += st.needles;
        spindles += st.spindles;
        slivers += st.slivers;
        caps += st.caps;
        EXPECT_EQ(st.needles + st.spindles + st.slivers + st.caps, st.degenerate_found);
        EXPECT_LT(st.volume_change, 1e-3);
        // Cells and nodes removed by collapses are reported with their maps.
        EXPECT_EQ(Index(r.removed_cells.size()),
            r.cells_before + Index(r.new_cells.size()) - m.num_cells());
    }
    std::cout << "degenerate found " << found << " (needles " << needles << ", spindles "
              << spindles << ", slivers " << slivers << ", caps " << caps << "), edges collapsed "
              << collapsed << ", left " << left << ", islands " << islands << "\n";
    EXPECT_GT(found, 0);
    EXPECT_GT(collapsed, 0);
    EXPECT_LT(left, found);
}

TEST(SnapCut, ThinStripsBetweenGridPlanesCutTheWholeSection) {
    // docs/decisions/0008: a blade between grid planes, sampled every 0.5 mm (strips a 40th of a
    // cell wide, one call per sample), crosses most tets on one or two edges only; judged against
    // the whole swept surface, the faces its closest nodes form are cut anyway. The blade spans
    // the block, so the cut must separate it, with each lip's area the block's section (0.1 x
    // 0.1 m) to rounding, and every Cut face in the blade's plane.
    for (double y : { 0.025, 0.0302 }) {
        auto m = tet_block(5); // 2 cm cells: grid planes at y = 0.02, 0.04
        const double v0 = m.rest_volume();
        cut::SnapCutter cutter(m);
        const auto tris
            = blade_sweep(Vec3(-0.005, y, -0.01), Vec3(-0.005, y, 0.11), Vec3(5e-4, 0, 0), 222);
        for (const auto& t : tris)
            expect_report_consistent(m, cutter.cut(std::span(&t, 1)));
        expect_report_consistent(m, cutter.finish_sweep());
        const auto inv = expect_ok(m, v0);
        EXPECT_EQ(inv.components, 2) << "y = " << y;
        double area = 0;
        Index off = 0;
        for (const auto& f : m.faces) {
            if (f.tag != mesh::FaceTag::Cut)
                continue;
            const Vec3 &a = m.rest[std::size_t(f.nodes[0])], &b = m.rest[std::size_t(f.nodes[1])],
                       &c = m.rest[std::size_t(f.nodes[2])];
            area += 0.5 * (b - a).cross(c - a).norm();
            for (Index k : f.nodes)
                off += std::abs(m.rest[std::size_t(k)].y() - y) > 1e-12;
        }
        EXPECT_NEAR(area / 2, 0.01, 1e-12) << "y = " << y;
        EXPECT_EQ(off, 0) << "y = " << y;
    }
}

TEST(SnapCut, ARandomSoupsWorkCountsItsPinchChecksAndSweepTestsAndTheBudgetStopsIt) {
    // Random triangles of ~4 cm through a 10 cm block of 1.7 cm cells: the held-back faces are
    // re-checked for pinches after every triangle and the checks scan the whole sweep, work the
    // touched cells do not show (CutReport::work, snap_cutter.hpp). One call of the whole soup
    // reports that work: at least its touched cells plus the checks and tests over their units.
    // The same soup under a budget of a quarter of it stops each call once the call's work
    // reaches the budget, so it takes several calls, every one but the last at the budget, and
    // every triangle is cut once.
    const std::vector<cut::Triangle> soup = random_soup(7, 60, 0.01, 0.09, 0.02);
    auto whole = tet_block(6);
    const double v0 = whole.rest_volume();
    cut::SnapCutter one(whole);
    const cut::CutReport all = one.cut(soup);
    const cut::SnapStats& st = one.stats();
    ASSERT_EQ(all.triangles, Index(soup.size()));
    ASSERT_GT(st.pinch_checks, 0);
    ASSERT_GT(st.sweep_tests, 0u);
    const double checks = double(st.pinch_checks) / double(cut::kPinchChecksPerWork)
        + double(st.sweep_tests) / double(cut::kSweepTestsPerWork);
    EXPECT_GE(all.work, checks);
    EXPECT_LE(all.work, checks + double(whole.num_cells()));
    expect_ok(whole, v0);

    auto parts = tet_block(6);
    cut::SnapCutter budgeted(parts);
    const Index budget = Index(std::ceil(all.work / 4));
    std::size_t done = 0;
    int calls = 0;
    while (done < soup.size()) {
        const cut::CutReport r = budgeted.cut(std::span(soup).subspan(done), budget);
        ASSERT_GT(r.triangles, 0);
        done += std::size_t(r.triangles);
        ++calls;
        if (done < soup.size()) {
            EXPECT_GE(r.work, double(budget)) << "call " << calls;
        }
        ASSERT_TRUE(expect_ok(parts, v0).ok()) << "call " << calls;
    }
    EXPECT_EQ(done, soup.size());
    EXPECT_GE(calls, 3);
}

TEST(SnapCut, AFarTriangleLeavesTheFacesHeldBackElsewhereAsTheyWere) {
    // A random soup in one corner of the block holds faces back (their edges would pinch). A
    // triangle cut in the opposite corner (beyond two longest edges of them) cannot free them:
    // it looks at none of them (no pinch check), they stay held, and the end of the sweep looks
    // at all of them again and leaves the same mesh as a sweep without the far triangle, up to
    // that triangle's own cut.
    const std::vector<cut::Triangle> soup = random_soup(3, 12, 0.01, 0.03, 0.01);
    auto a = tet_block(10), b = tet_block(10);
    const double v0 = a.rest_volume();
    cut::SnapCutter ca(a), cb(b);
    Index checks = 0;
    for (std::size_t i = 0; i < soup.size(); ++i) {
        ca.cut(std::span(&soup[i], 1));
        checks += ca.stats().pinch_checks;
        cb.cut(std::span(&soup[i], 1));
    }
    ASSERT_GT(checks, 0) << "the soup should hold faces back";
    // The opposite corner (x, y, z > 7 cm): > 4 cm from the soup's nodes; 2 longest edges of
    // the 1 cm Kuhn cells are 3.5 cm.
    const auto far
        = square(Vec3(0.085, 0.085, 0.085), Vec3::UnitX(), Vec3(0, 1, 1).normalized(), 0.012);
    const cut::CutReport r = ca.cut(far);
    EXPECT_FALSE(r.cut_faces.empty());
    // Its pinch checks are those of its own faces: the same triangle on an uncut block.
    auto c = tet_block(10);
    cut::SnapCutter cc(c);
    cc.cut(far);
    EXPECT_EQ(ca.stats().pinch_checks, cc.stats().pinch_checks);
    // The soup's held faces are left for the end of the sweep, which cuts them as the sweep
    // without the far triangle does.
    const cut::CutReport end_a = ca.finish_sweep(), end_b = cb.finish_sweep(),
                         end_c = cc.finish_sweep();
    EXPECT_TRUE(expect_ok(a, v0).ok());
    EXPECT_TRUE(expect_ok(b, v0).ok());
    EXPECT_GT(end_b.cut_faces.size(), 0u);
    EXPECT_EQ(end_a.cut_faces.size(), end_b.cut_faces.size() + end_c.cut_faces.size());
}
