// Degeneracy removal of face snapping (002 sec. 3.2.3): each removal path (needle collapse,
// spindle split-and-collapse, sliver, cap, cut-free) runs on hand-built configurations and on
// cuts of irregular meshes, and leaves no degenerate tet unreported, positive tets, a closed
// oriented surface, a consistent node map and a rest volume change below 1e-3.
#include "test_snap_common.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

using namespace polycut;
using namespace snaptest;

namespace {

// The node map sends every surviving pre-call node to a node at its (possibly moved) position.
void expect_node_map(const mesh::Mesh& before, const mesh::Mesh& after, const cut::CutReport& r) {
    if (r.node_map.empty()) {
        EXPECT_EQ(r.removed_nodes.size(), 0u);
        return;
    }
    std::vector<char> moved(after.rest.size(), 0);
    for (const auto& [n, X0] : r.moved_nodes)
        moved[std::size_t(n)] = 1;
    Index removed = 0;
    for (Index n = 0; n < r.nodes_before; ++n) {
        const Index k = r.node_map[std::size_t(n)];
        if (k == kNone) {
            ++removed;
            continue;
        }
        ASSERT_LT(k, after.num_nodes());
        if (!moved[std::size_t(k)]) {
            EXPECT_LT((after.rest[std::size_t(k)] - before.rest[std::size_t(n)]).norm(), 1e-15);
        }
    }
    EXPECT_EQ(removed, Index(r.removed_nodes.size()));
}

// A 4^3 Kuhn block with its centre node moved from its grid position towards a point Q of the
// boundary of its star, to a fraction t of the way back from Q.
struct Configured {
    mesh::Mesh m;
    Index v = kNone;
};
Configured center_moved(const std::function<Vec3(const mesh::Mesh&, Index)>& target, double t) {
    Configured c { tet_block(4), kNone };
    for (Index n = 0; n < c.m.num_nodes(); ++n)
        if ((c.m.rest[std::size_t(n)] - Vec3::Constant(0.05)).norm() < 1e-12)
            c.v = n;
    const Vec3 X = c.m.rest[std::size_t(c.v)];
    const Vec3 Q = target(c.m, c.v);
    c.m.rest[std::size_t(c.v)] = Q + t * (X - Q);
    return c;
}

// The face of the tet `cell` opposite node v (the star's boundary there), as three node ids.
std::array<Index, 3> link_face(const mesh::Mesh& m, Index cell, Index v) {
    std::array<Index, 3> f {};
    std::size_t j = 0;
    for (Index n : m.cells[std::size_t(cell)].nodes)
        if (n != v)
            f[j++] = n;
    return f;
}

Index first_cell_of(const mesh::Mesh& m, Index v) {
    for (Index c = 0; c < m.num_cells(); ++c)
        for (Index n : m.cells[std::size_t(c)].nodes)
            if (n == v)
                return c;
    return kNone;
}

void print_stats(const char* what, const cut::SnapStats& st) {
    std::cout << what << ": found " << st.degenerate_found << " (n/s/sl/c " << st.needles << "/"
              << st.spindles << "/" << st.slivers << "/" << st.caps << "), removed n/s/sl/c "
              << st.needles_removed << "/" << st.spindles_removed << "/" << st.slivers_removed
              << "/" << st.caps_removed << ", cut free " << st.cut_free << ", left "
              << st.degenerate_left << ", collapses " << st.edges_collapsed << ", volume change "
              << st.volume_change << "\n";
}

// Runs remove_degeneracies on m and checks the issue 5 item 6 invariants for face snapping.
cut::SnapStats clean(mesh::Mesh& m, const cut::SnapOptions& opt = {}) {
    const mesh::Mesh before = m;
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m, opt);
    const auto r = cutter.remove_degeneracies();
    expect_report_consistent(m, r);
    expect_node_map(before, m, r);
    // Nodes that existed before the call keep their ids, even when the tets that used them are
    // gone (the caller then updates only the changed cells, issue 12 item 5).
    EXPECT_TRUE(r.node_map.empty());
    EXPECT_GE(m.num_nodes(), before.num_nodes());
    const auto inv = expect_ok(m, v0);
    EXPECT_TRUE(inv.finite);
    const auto& st = cutter.stats();
    EXPECT_LT(st.volume_change, 1e-3);
    EXPECT_EQ(quality(m, opt).degenerate, st.degenerate_left);
    return st;
}

} // namespace

Vec3 face_centroid(const mesh::Mesh& m, Index v) {
    const auto f = link_face(m, first_cell_of(m, v), v);
    return (m.rest[std::size_t(f[0])] + m.rest[std::size_t(f[1])] + m.rest[std::size_t(f[2])]) / 3;
}
Vec3 edge_midpoint(const mesh::Mesh& m, Index v) {
    const auto f = link_face(m, first_cell_of(m, v), v);
    return (m.rest[std::size_t(f[0])] + m.rest[std::size_t(f[1])]) / 2;
}
Vec3 link_node(const mesh::Mesh& m, Index v) {
    return m.rest[std::size_t(link_face(m, first_cell_of(m, v), v)[0])];
}

TEST(SnapDegenerate, NeedleIsCollapsed) {
    // The centre node 0.3 % of the way from a link node: every tet on that edge has a short edge
    // and no large angle.
    auto c = center_moved(link_node, 0.003);
    cut::SnapOptions opt;
    EXPECT_GT(quality(c.m, opt).degenerate, 0);
    const auto st = clean(c.m, opt);
    print_stats("needle", st);
    EXPECT_GT(st.needles, 0);
    EXPECT_GT(st.needles_removed, 0);
    EXPECT_EQ(st.degenerate_left, 0);
    EXPECT_EQ(st.cut_free, 0);
    EXPECT_EQ(quality(c.m, opt).degenerate, 0);
}

TEST(SnapDegenerate, SpindleIsSplitAndCollapsed) {
    // Over the midpoint of a link edge: the tets on that edge get one angle near pi.
    auto c = center_moved(edge_midpoint, 0.003);
    cut::SnapOptions opt;
    const auto st = clean(c.m, opt);
    print_stats("spindle", st);
    EXPECT_GT(st.spindles, 0);
    EXPECT_GT(st.spindles_removed, 0);
    EXPECT_GT(st.edges_split, 0);
    EXPECT_EQ(quality(c.m, opt).degenerate, 0);
}

TEST(SnapDegenerate, SliverAndCapAreSplitAndCollapsed) {
    // Over the centroid of a link face: that tet is a cap (three angles near pi); the Kuhn link
    // face is half of a planar rhombus, so the tet on the other half is a sliver (two).
    auto c = center_moved(face_centroid, 0.003);
    cut::SnapOptions opt;
    const auto st = clean(c.m, opt);
    print_stats("sliver+cap", st);
    EXPECT_GT(st.slivers, 0);
    EXPECT_GT(st.caps, 0);
    EXPECT_GT(st.slivers_removed, 0);
    EXPECT_GT(st.caps_removed, 0);
    EXPECT_GT(st.faces_split, 0);
    EXPECT_EQ(quality(c.m, opt).degenerate, 0);
    // Interior collapses conserve the rest volume.
    EXPECT_LT(st.volume_change, 1e-12);
}

TEST(SnapDegenerate, IncollapsibleTetsAreCutFreeOrReported) {
    // Ten times flatter: after the sliver is collapsed the cap is left with no valid collapse
    // (the snap_min_aspect guard refuses them) and is cut free; its tiny volume is reported.
    auto c = center_moved(face_centroid, 0.001);
    mesh::Mesh copy = c.m;
    cut::SnapOptions opt;
    const auto st = clean(c.m, opt);
    print_stats("cut free", st);
    EXPECT_GT(st.cut_free, 0);
    EXPECT_GT(st.volume_change, 0);
    EXPECT_LT(st.volume_change, 1e-3);
    EXPECT_EQ(quality(c.m, opt).degenerate, 0);
    // Without cutting free they are left, positive and counted.
    opt.cut_free = false;
    const auto kept = clean(copy, opt);
    EXPECT_EQ(kept.cut_free, 0);
    EXPECT_GT(kept.degenerate_left, 0);
    EXPECT_EQ(quality(copy, opt).degenerate, kept.degenerate_left);
}

TEST(SnapDegenerate, CutsOfJitteredGridsRemoveEveryKind) {
    // Through-cuts of jittered Kuhn and five-tet blocks in varied directions: snapping makes
    // flat tets of several kinds; after each cut no degenerate tet is left unreported.
    std::mt19937 rng(5u);
    cut::SnapStats sum;
    Index removed = 0;
    for (auto split : { mesh::TetSplit::Kuhn6, mesh::TetSplit::Five })
        for (int k = 0; k < 20; ++k) {
            auto m = jittered_block(6, split, 0.2, rng);
            const cut::SnapOptions opt;
            ASSERT_EQ(quality(m, opt).degenerate, 0);
            const mesh::Mesh before = m;
            const double v0 = m.rest_volume();
            cut::SnapCutter cutter(m, opt);
            const Vec3 n = Vec3(1, 0.13 * k, 0.31 - 0.05 * k).normalized();
            const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.cross(u);
            const auto r = cutter.cut(square(Vec3(0.047 + 0.001 * k, 0.05, 0.05), u, v, 0.2));
            expect_report_consistent(m, r);
            expect_node_map(before, m, r);
            EXPECT_TRUE(r.node_map.empty()) << "cut " << k << ": the old nodes keep their ids";
            const auto inv = expect_ok(m, v0);
            ASSERT_TRUE(inv.ok()) << "cut " << k << ": " << inv.first_problem;
            const auto& st = cutter.stats();
            EXPECT_LT(st.volume_change, 1e-3);
            EXPECT_EQ(quality(m, opt).degenerate, st.degenerate_left) << "cut " << k;
            // The tets a collapse deleted give their ids to the last tets: no other tet is
            // renumbered (the whole face table and a shift of every later tet are not needed).
            EXPECT_EQ(st.face_tables_whole, 0) << "cut " << k;
            Index moved = 0;
            for (std::size_t c = 0; c < r.cell_map.size(); ++c)
                moved += r.cell_map[c] != kNone && r.cell_map[c] != Index(c) ? 1 : 0;
            EXPECT_LE(moved, Index(r.removed_cells.size())) << "cut " << k;
            sum.face_tables_local += st.face_tables_local;
            removed += Index(r.removed_cells.size());
            for (auto [to, from] : { std::pair { &sum.needles_removed, st.needles_removed },
                     { &sum.spindles_removed, st.spindles_removed },
                     { &sum.slivers_removed, st.slivers_removed },
                     { &sum.caps_removed, st.caps_removed }, { &sum.cut_free, st.cut_free },
                     { &sum.degenerate_found, st.degenerate_found },
                     { &sum.degenerate_left, st.degenerate_left } })
                *to += from;
        }
    print_stats("jittered cuts", sum);
    EXPECT_GT(sum.needles_removed, 0);
    EXPECT_GT(sum.spindles_removed, 0);
    EXPECT_GT(sum.slivers_removed, 0);
    EXPECT_GT(sum.cut_free, 0);
    EXPECT_GT(removed, 0); // tets were deleted, through the local face rebuild
    EXPECT_GT(sum.face_tables_local, 0);
}

TEST(SnapIslands, ThroughCutsOfJitteredBlocksGiveTwoPieces) {
    // On a jittered mesh closest-node selection can wrap a tet lying on the far side of the
    // sweep (its apex snap refused), which used to come off as a tiny extra component; and the
    // hole such a tet leaves in the selected surface can pinch an edge, whose faces used to stay
    // pending, leaving the halves joined. A through-cut must give exactly the two halves.
    std::mt19937 rng(5u);
    Index exact = 0, merged = 0, pinches = 0, local = 0;
    for (auto split : { mesh::TetSplit::Kuhn6, mesh::TetSplit::Five })
        for (int k = 0; k < 20; ++k) {
            auto m = jittered_block(6, split, 0.2, rng);
            const double v0 = m.rest_volume();
            cut::SnapCutter cutter(m);
            const Vec3 n = Vec3(1, 0.13 * k, 0.31 - 0.05 * k).normalized();
            const Vec3 u = n.cross(Vec3::UnitZ()).normalized(), v = n.cross(u);
            const auto r = cutter.cut(square(Vec3(0.047 + 0.001 * k, 0.05, 0.05), u, v, 0.2));
            expect_report_consistent(m, r);
            const auto inv = expect_ok(m, v0);
            merged += cutter.stats().islands_merged;
            pinches += cutter.stats().pinches_split;
            local += cutter.stats().face_tables_local;
            exact += inv.components == 2 ? 1 : 0;
            EXPECT_EQ(inv.components, 2)
                << (split == mesh::TetSplit::Kuhn6 ? "Kuhn" : "five-tet") << " cut " << k;
            EXPECT_EQ(cutter.stats().faces_pending, 0) << "cut " << k;
        }
    std::cout << "through-cuts with exactly 2 pieces: " << exact << " of 40, pieces glued back "
              << merged << ", pinched edges split " << pinches
              << ", face tables made again locally " << local << "\n";
    EXPECT_GT(merged, 0);
    EXPECT_GT(pinches, 0);
    // Opening the pinches went through the local face rebuild (decision 0016), whose table
    // is checked for consistency under POLYCUT_CHECK_UNDO=1 and here by the invariants.
    EXPECT_GT(local, 0);
}
