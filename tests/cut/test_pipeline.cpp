// cut::CutPipeline (issue 12 item 6): one validation with the triangle's index and corner, a
// typed result, the budget of changed cells that defers the rest of a sweep to the next call
// (and cuts the same in the end), the Failed contract (mesh half cut, the caller undoes), and the
// undo journal: undo() gives back the mesh before the last call exactly, whatever the call did.
#include "polycut/cut/completeness.hpp"
#include "polycut/cut/fault_injection.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/cut/pipeline.hpp"
#include "polycut/mesh/builders.hpp"
#include "test_pipeline_common.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <gtest/gtest.h>
#include <limits>

namespace polycut::cut {
namespace {

using pipelinetest::block;
using pipelinetest::expect_cut_invariants;
using pipelinetest::options;

/// A blade at y = 0.43 (between grid planes) from z = 1.2 down to z = 0.4, moved along x in
/// `n` steps through the whole block: 2 n sweep triangles.
std::vector<Triangle> stroke(int n) {
    std::vector<Triangle> out;
    auto at = [&](int k) { return -0.2 + 1.4 * double(k) / double(n); };
    for (int k = 0; k < n; ++k) {
        const Vec3 a0(at(k), 0.43, 1.2), b0(at(k), 0.43, 0.4);
        const Vec3 a1(at(k + 1), 0.43, 1.2), b1(at(k + 1), 0.43, 0.4);
        out.push_back({ a0, b0, a1 });
        out.push_back({ b0, b1, a1 });
    }
    return out;
}

/// Field by field, with the first difference in the message.
void expect_same_mesh(const mesh::Mesh& a, const mesh::Mesh& b) {
    ASSERT_EQ(a.rest.size(), b.rest.size());
    for (std::size_t i = 0; i < a.rest.size(); ++i)
        ASSERT_EQ(a.rest[i], b.rest[i]) << "node " << i;
    ASSERT_EQ(a.faces.size(), b.faces.size());
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
        ASSERT_EQ(a.faces[f].nodes, b.faces[f].nodes) << "face " << f;
        ASSERT_EQ(a.faces[f].owner, b.faces[f].owner) << "face " << f;
        ASSERT_EQ(a.faces[f].neighbour, b.faces[f].neighbour) << "face " << f;
        ASSERT_EQ(a.faces[f].tag, b.faces[f].tag) << "face " << f;
        ASSERT_EQ(a.faces[f].parent, b.faces[f].parent) << "face " << f;
    }
    ASSERT_EQ(a.cells.size(), b.cells.size());
    for (std::size_t c = 0; c < a.cells.size(); ++c) {
        ASSERT_EQ(a.cells[c].nodes, b.cells[c].nodes) << "cell " << c;
        ASSERT_EQ(a.cells[c].faces, b.cells[c].faces) << "cell " << c;
        ASSERT_EQ(a.cells[c].shape, b.cells[c].shape) << "cell " << c;
        ASSERT_EQ(a.cells[c].parent, b.cells[c].parent) << "cell " << c;
    }
}

class Pipeline : public ::testing::TestWithParam<bool> { };

TEST_P(Pipeline, RejectsWithTheTriangleAndCornerAndChangesNothing) {
    mesh::Mesh m = block(GetParam());
    const mesh::Mesh uncut = m;
    CutPipeline p(m, uncut, options(GetParam()));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<Triangle> tris = stroke(2);
    bool changed = false;
    auto watch = [&] { changed = true; };

    tris[2][1] = Vec3(0.5, nan, 0.5);
    CutResult r = p.cut(tris, m.rest, 0, watch);
    EXPECT_EQ(r.status, CutStatus::Rejected);
    EXPECT_EQ(r.rejected_triangle, 2);
    EXPECT_EQ(r.rejected_corner, 1);
    EXPECT_NE(r.reason.find("finite"), std::string::npos) << r.reason;

    tris = stroke(2);
    tris[3][0] = Vec3(1e6, 0, 0); // 1000 km away
    r = p.cut(tris, m.rest, 0, watch);
    EXPECT_EQ(r.status, CutStatus::Rejected);
    EXPECT_EQ(r.rejected_triangle, 3);
    EXPECT_EQ(r.rejected_corner, 0);

    tris = stroke(2);
    tris[1] = { Vec3(0, 0.5, 0.5), Vec3(0.5, 0.5, 0.5), Vec3(1, 0.5, 0.5) }; // collinear
    r = p.cut(tris, m.rest, 0, watch);
    EXPECT_EQ(r.status, CutStatus::Rejected);
    EXPECT_EQ(r.rejected_triangle, 1);
    EXPECT_EQ(r.rejected_corner, -1);

    tris[1] = { Vec3(0, 0.5, 0.5), Vec3(0, 0.5, 0.5), Vec3(1, 0.5, 0.7) }; // coincident
    r = p.cut(tris, m.rest, 0, watch);
    EXPECT_EQ(r.status, CutStatus::Rejected);
    EXPECT_EQ(r.rejected_triangle, 1);

    EXPECT_EQ(p.cut({}, m.rest, 0, watch).status, CutStatus::Rejected);
    EXPECT_FALSE(changed) << "a rejected cut must not touch the mesh";
    EXPECT_EQ(m.num_cells(), uncut.num_cells());
    EXPECT_EQ(m.num_nodes(), uncut.num_nodes());
}

TEST_P(Pipeline, TrianglesOutsideOrTooSmallAreSkippedWithoutAChange) {
    mesh::Mesh m = block(GetParam());
    const mesh::Mesh uncut = m;
    CutPipeline p(m, uncut, options(GetParam()));
    bool changed = false;
    const std::vector<Triangle> tris { { Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5) },
        { Vec3(0.5, 0.5, 0.5), Vec3(0.5 + 1e-8, 0.5, 0.5), Vec3(0.5, 0.5 + 1e-8, 0.5) } };
    const CutResult r = p.cut(tris, m.rest, 0, [&] { changed = true; });
    EXPECT_EQ(r.status, CutStatus::Applied);
    EXPECT_EQ(r.skipped, 2u);
    EXPECT_EQ(r.consumed, 2u);
    EXPECT_FALSE(changed);
}

TEST_P(Pipeline, BudgetDefersTheRestAndCutsTheSameInTheEnd) {
    const bool snap = GetParam();
    const std::vector<Triangle> tris = stroke(8);
    // Reference: the whole stroke in one call.
    mesh::Mesh whole = block(snap);
    const mesh::Mesh uncut = whole;
    CutPipeline one(whole, uncut, options(snap));
    const CutResult all = one.cut(tris, whole.rest);
    ASSERT_EQ(all.status, CutStatus::Applied) << all.reason;
    ASSERT_TRUE(one.end_stroke().ok()); // face snapping cuts the faces it held back
    const std::size_t budget = all.report.changed_cells.size() / 6;
    ASSERT_GT(budget, 0u);

    // The same stroke under a budget of a sixth of the cells it changes: passed again, the
    // deferred rest each time, until nothing is left.
    mesh::Mesh m = uncut;
    CutPipeline p(m, uncut, options(snap));
    std::vector<Triangle> left = tris;
    int calls = 0;
    double swept = 0;
    while (!left.empty() && calls < 100) {
        const CutResult r = p.cut(left, m.rest, Index(budget));
        ASSERT_TRUE(r.ok()) << r.reason;
        ++calls;
        EXPECT_GE(r.consumed, 1u) << "each call must advance";
        EXPECT_EQ(r.consumed + r.deferred, left.size());
        // A call stops once it has reached the budget; the triangle that crossed it may
        // overshoot by what one triangle changes.
        if (r.status == CutStatus::Deferred) {
            EXPECT_GE(r.report.changed_cells.size(), budget);
        }
        swept += r.swept_area;
        left.erase(left.begin(), left.begin() + std::ptrdiff_t(r.consumed));
    }
    EXPECT_TRUE(left.empty());
    ASSERT_TRUE(p.end_stroke().ok());
    EXPECT_GE(calls, 3) << "the budget should have split the stroke";
    // Same swept area, same opened area (both lips), a valid mesh.
    EXPECT_NEAR(swept, all.swept_area, 1e-12);
    EXPECT_NEAR(cut_face_area(m), cut_face_area(whole), 0.02 * cut_face_area(whole));
    EXPECT_NEAR(cut_face_area(m) / (2 * swept), 1.0, snap ? 0.05 : 0.01);
    expect_cut_invariants(m, uncut, snap);
}

TEST_P(Pipeline, FailureReportsAndLeavesTheRestoreToTheCaller) {
    const bool snap = GetParam();
    mesh::Mesh m = block(snap);
    const mesh::Mesh uncut = m;
    CutPipeline p(m, uncut, options(snap));
    bool snapshot = false;
    inject_cut_failures(1);
    const CutResult r = p.cut(stroke(2), m.rest, 0, [&] { snapshot = true; });
    inject_cut_failures(0);
    EXPECT_EQ(r.status, CutStatus::Failed);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.reason.find("injected"), std::string::npos) << r.reason;
    EXPECT_TRUE(snapshot) << "the caller must have been asked to snapshot before the change";
    // The caller undoes: the mesh is the uncut one again, and the next cut works.
    p.undo();
    expect_same_mesh(m, uncut);
    const CutResult again = p.cut(stroke(2), m.rest);
    EXPECT_EQ(again.status, CutStatus::Applied) << again.reason;
    EXPECT_GT(again.swept_area, 0.0);
}

TEST_P(Pipeline, UndoGivesBackTheMeshBeforeTheLastCallExactly) {
    // Strokes on the mesh's features (a blade in a grid plane, through nodes, along a cut
    // already made, sliver-thin beside a grid plane) and between them, sample by sample as a
    // scalpel sends them. Before each call the test copies the mesh; every third call is
    // undone and must give that copy back field by field, then is cut again. The journal's own
    // check (POLYCUT_CHECK_UNDO) compares its mirror with the mesh after every commit.
    const bool snap = GetParam();
    ::setenv("POLYCUT_CHECK_UNDO", "1", 1);
    mesh::Mesh m = block(snap, 5);
    const mesh::Mesh uncut = m;
    CutPipeline p(m, uncut, options(snap));
    struct Blade {
        double y; ///< plane of the blade [m]
        double z0, z1; ///< top and bottom edge [m]
    };
    const Blade blades[] = { { 0.4, 1.2, 0.3 }, // a grid plane (0.2 spacing)
        { 0.4, 1.2, 0.5 }, // again along that cut
        { 0.61, 1.2, 0.45 }, // between grid planes
        { 0.6 + 1e-5, 1.2, 0.55 }, // a sliver away from a grid plane
        { 0.2, 1.2, 0.6 } }; // through grid nodes (z 0.6 is a node plane)
    int calls = 0, undone = 0;
    for (const Blade& b : blades) {
        constexpr int kSamples = 7;
        for (int k = 0; k < kSamples; ++k) {
            auto x = [&](int i) { return -0.2 + 1.4 * double(i) / kSamples; };
            const std::vector<Triangle> sweep { { Vec3(x(k), b.y, b.z0), Vec3(x(k), b.y, b.z1),
                                                    Vec3(x(k + 1), b.y, b.z0) },
                { Vec3(x(k), b.y, b.z1), Vec3(x(k + 1), b.y, b.z1), Vec3(x(k + 1), b.y, b.z0) } };
            const mesh::Mesh before = m;
            CutResult r = p.cut(sweep, m.rest);
            ASSERT_TRUE(r.ok()) << r.reason;
            if (++calls % 3 == 0 && r.report.topology_changed) {
                p.undo();
                expect_same_mesh(m, before);
                if (::testing::Test::HasFatalFailure())
                    return;
                ++undone;
                r = p.cut(sweep, m.rest);
                ASSERT_TRUE(r.ok()) << r.reason;
            }
        }
        p.end_stroke();
    }
    // undo_all(): back to the last accept(), across several calls (the server's failed step).
    p.accept();
    const mesh::Mesh accepted = m;
    for (double y : { 0.3, 0.7 }) {
        const std::vector<Triangle> sweep { { Vec3(-0.2, y, 1.2), Vec3(-0.2, y, 0.5),
            Vec3(1.2, y, 1.2) } };
        ASSERT_TRUE(p.cut(sweep, m.rest).ok());
    }
    p.end_stroke();
    p.undo_all();
    expect_same_mesh(m, accepted);
    ::unsetenv("POLYCUT_CHECK_UNDO");
    EXPECT_GE(undone, 5);
    expect_cut_invariants(m, uncut, snap);
    // At least one call renumbered (merged slivers or compacted nodes), so the journal's whole
    // copy was exercised as well as the local one. Cell splitting merges cut faces in its
    // calls: the mirror moved its faces along those compactions (checked against the mesh by
    // POLYCUT_CHECK_UNDO at every sync) instead of copying the mesh.
    std::printf("calls %d, undone %d, whole-mesh mirror copies %llu, face moves %llu\n", calls,
        undone, static_cast<unsigned long long>(p.whole_mesh_copies()),
        static_cast<unsigned long long>(p.mirror_face_moves()));
    if (!snap) {
        EXPECT_GT(p.mirror_face_moves(), 0u);
    }
}

TEST_P(Pipeline, APreparedPipelineCutsExactlyAsOneThatBuildsOnItsFirstCall) {
    // prepare() builds at load what the first call would build (the cutter, the world grid's
    // flat node lists, the face-snapping cutter's grid): the cuts must not change by one bit.
    // Under POLYCUT_CHECK_UNDO the world grid compares its flat lists with the mesh and the
    // snap grid its candidates with a pass over every tet, at every call.
    const bool snap = GetParam();
    ::setenv("POLYCUT_CHECK_UNDO", "1", 1);
    mesh::Mesh a = block(snap, 5), b = a;
    const mesh::Mesh uncut = a;
    CutPipeline prepared(a, uncut, options(snap)), lazy(b, uncut, options(snap));
    prepared.prepare();
    const std::vector<Triangle> sweep = stroke(6);
    for (std::size_t k = 0; k < sweep.size(); k += 2) {
        const std::span<const Triangle> sample(sweep.data() + k, 2);
        const CutResult ra = prepared.cut(sample, a.rest), rb = lazy.cut(sample, b.rest);
        ASSERT_EQ(ra.status, rb.status) << "sample " << k / 2;
        ASSERT_TRUE(ra.ok()) << ra.reason;
    }
    prepared.end_stroke();
    lazy.end_stroke();
    ::unsetenv("POLYCUT_CHECK_UNDO");
    expect_same_mesh(a, b);
    expect_cut_invariants(a, uncut, snap);
    EXPECT_GT(std::count_if(a.faces.begin(), a.faces.end(),
                  [](const mesh::Face& f) { return f.tag == mesh::FaceTag::Cut; }),
        20);
}

TEST_P(Pipeline, CountsTheInvertedTetsAroundTheBlade) {
    // A body folded under a load has tets turned inside out; there the world-to-rest map is not
    // one-to-one and the cut can only follow the fold approximately (docs/scenes.md). The call
    // counts them, for the simulation's warning; an unfolded body has none.
    const bool snap = GetParam();
    const std::vector<Triangle> sweep = stroke(4);
    for (bool fold : { false, true }) {
        mesh::Mesh m = block(true, 6); // tets for both cutters
        const mesh::Mesh uncut = m;
        std::vector<Vec3> positions = m.rest;
        // an interior node near the blade pushed 2.4 cells down, through the tets below it
        Index pushed = 0;
        for (Index n = 0; n < m.num_nodes(); ++n)
            if ((m.rest[std::size_t(n)] - Vec3(0.5, 0.5, 2.0 / 3)).norm()
                < (m.rest[std::size_t(pushed)] - Vec3(0.5, 0.5, 2.0 / 3)).norm())
                pushed = n;
        if (fold)
            positions[std::size_t(pushed)] += Vec3(0, 0, -0.4);
        Index expected = 0;
        for (const mesh::Cell& c : m.cells) {
            const auto x = [&](int k) { return positions[std::size_t(c.nodes[std::size_t(k)])]; };
            if ((x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0)) < 0)
                ++expected;
        }
        CutPipeline p(m, uncut, options(snap));
        const CutResult r = p.cut(sweep, positions);
        if (!fold) {
            EXPECT_EQ(r.inverted_cells, 0u);
            continue;
        }
        ASSERT_GT(expected, 0);
        EXPECT_GT(r.inverted_cells, 0u);
        EXPECT_LE(r.inverted_cells, std::size_t(expected)); // only those around the sweep
    }
}

TEST_P(Pipeline, TrianglesMappedThroughCrushedTissueAreSkippedAndCounted) {
    // The same stroke through a block shrunk uniformly (an affine map, so the fit is exact): at
    // 0.6 of its size each rest triangle is 1.7 times as long (2.8 times as large) as its world
    // self and the block is cut as at rest; at a fifth, five times as long (beyond
    // kMaxRestStretch = 4, what only a fold or a crush gives): every triangle is skipped and
    // counted in `stretched`, and nothing changes.
    const bool snap = GetParam();
    for (double scale : { 0.6, 0.2 }) {
        mesh::Mesh m = block(true, 6);
        const mesh::Mesh uncut = m;
        std::vector<Vec3> positions = m.rest;
        for (Vec3& x : positions)
            x *= scale;
        std::vector<Triangle> sweep = stroke(4);
        for (Triangle& t : sweep)
            for (Vec3& x : t)
                x *= scale;
        CutPipeline p(m, uncut, options(snap));
        bool changed = false;
        const CutResult r = p.cut(sweep, positions, 0, [&] { changed = true; });
        EXPECT_EQ(r.status, CutStatus::Applied) << "scale " << scale;
        EXPECT_EQ(r.consumed, sweep.size()) << "scale " << scale;
        if (scale == 0.6) {
            EXPECT_EQ(r.stretched, 0u);
            EXPECT_TRUE(changed);
            EXPECT_NEAR(r.swept_area, 0.6, 1e-9); // 1 x 0.6 of the blade inside, at rest
            expect_cut_invariants(m, uncut, snap);
        } else {
            EXPECT_EQ(r.stretched, sweep.size());
            EXPECT_EQ(r.skipped, sweep.size());
            EXPECT_FALSE(changed);
            EXPECT_EQ(m.num_cells(), uncut.num_cells());
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Cutters, Pipeline, ::testing::Values(false, true),
    [](const ::testing::TestParamInfo<bool>& param) {
        return param.param ? std::string("FaceSnapping") : std::string("CellSplitting");
    });

} // namespace
} // namespace polycut::cut
