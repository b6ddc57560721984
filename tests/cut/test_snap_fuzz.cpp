// Random sweeps on a small tet block with all invariants after each (issue 5 item 8, fixed seed).
#include "test_snap_common.hpp"

#include <random>

using namespace polycut;
using namespace snaptest;

TEST(SnapFuzz, RandomSweepsKeepInvariants) {
    auto m = tet_block(3);
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m);
    std::mt19937 rng(20240502u);
    std::uniform_real_distribution<double> U(-0.03, 0.13);
    for (int i = 0; i < 300; ++i) {
        // A sweep of 1-4 connected triangles (a fan around a random point).
        std::vector<cut::Triangle> tris;
        const Vec3 o(U(rng), U(rng), U(rng));
        Vec3 prev(U(rng), U(rng), U(rng));
        const int k = 1 + int(rng() % 4);
        for (int j = 0; j < k; ++j) {
            const Vec3 next(U(rng), U(rng), U(rng));
            const cut::Triangle t { o, prev, next };
            if ((t[1] - t[0]).cross(t[2] - t[0]).norm() > 1e-4)
                tris.push_back(t);
            prev = next;
        }
        if (tris.empty())
            continue;
        const auto r = cutter.cut(tris);
        expect_report_consistent(m, r);
        const auto inv = expect_ok(m, v0);
        ASSERT_TRUE(inv.ok()) << "sweep " << i << ": " << inv.first_problem;
        if (rng() % 3 == 0)
            cutter.end_sweep();
    }
}

TEST(SnapFuzz, RandomSweepsWithDegeneracyRemoval) {
    // A permissive snap guard makes flat tets common, so collapses run often.
    cut::SnapOptions opt;
    opt.snap_min_aspect = 1e-6;
    auto m = tet_block(3);
    const double v0 = m.rest_volume();
    cut::SnapCutter cutter(m, opt);
    std::mt19937 rng(77u);
    std::uniform_real_distribution<double> U(-0.03, 0.13);
    Index collapsed = 0;
    for (int i = 0; i < 200; ++i) {
        const cut::Triangle t { Vec3(U(rng), U(rng), U(rng)), Vec3(U(rng), U(rng), U(rng)),
            Vec3(U(rng), U(rng), U(rng)) };
        if ((t[1] - t[0]).cross(t[2] - t[0]).norm() < 1e-4)
            continue;
        const auto r = cutter.cut(std::span(&t, 1));
        collapsed += cutter.stats().edges_collapsed;
        expect_report_consistent(m, r);
        const auto inv = expect_ok(m, v0);
        ASSERT_TRUE(inv.ok()) << "sweep " << i << ": " << inv.first_problem;
        cutter.end_sweep();
    }
    std::cout << "collapses over the fuzz run: " << collapsed << "\n";
}
