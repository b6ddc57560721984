// The embedded surface through the facade (issue 15 item 2): the surface the simulation hands
// out (stream, renderer) is the embedded one, it follows the tissue, contact samples it, and
// a cut splits it along the blade and closes it with detailed lips (tag 2).
#include "../embed/uv_sphere.hpp"
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <map>

using namespace polycut;

namespace {
/// A UV sphere of radius r about c as an OFF file in the temp directory; returns its path.
std::string sphere_off(const Vec3& c, double r, int rings, int segments) {
    std::vector<Vec3> v;
    std::vector<std::array<Index, 3>> t;
    test::uv_sphere(c, r, rings, segments, v, t);
    const auto path = std::filesystem::temp_directory_path() / "polycut_test_embedded_sphere.off";
    std::ofstream out(path);
    out.precision(17);
    out << "OFF\n" << v.size() << " " << t.size() << " 0\n";
    for (const Vec3& p : v)
        out << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const auto& f : t)
        out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
    return path.string();
}

std::string block_text(
    const std::string& path, const std::string& method, const std::string& extra) {
    const bool tet = method == "tet";
    return R"({"name": "embedded_block",
      "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.04],
                   "cells": [4, 4, 4], "elements": ")"
        + std::string(tet ? "tet" : "hex") + R"("},
      "method": ")"
        + method + R"(",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000, "rayleigh_mass": 8},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "cholmod"},
      "embedded": {"path": ")"
        + path + R"("})" + extra + "}";
}
} // namespace

TEST(SimEmbedded, TheSurfaceIsTheEmbeddedOneAndFollowsTheTissue) {
    // A 1.9 cm sphere of 2,300 triangles inside a 4 cm block of 1 cm cells, fixed at its
    // base, pulled by gravity: the surface handed out is the sphere (its vertex and triangle
    // counts, all skin), at rest exactly where the file puts it, and under load it moves with
    // the tissue (the top of the sphere sags like the block's middle).
    const std::string path = sphere_off(Vec3(0, 0, 0.02), 0.019, 24, 48);
    sim::Simulation s(scene::parse_scene(block_text(path, "hex", R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
      "probes": [{"name": "top", "point": [0, 0, 0.039]}],
      "loads": {"gravity": [0, 0, -9.81]})")));
    sim::Surface surface = s.surface();
    const std::size_t nv = 1 + 23 * 48 + 1, nt = 2 * 48 * 23;
    ASSERT_EQ(surface.positions.size(), 3 * nv);
    ASSERT_EQ(surface.triangles.size(), 3 * nt);
    for (const auto tag : surface.tags)
        ASSERT_EQ(tag, 1);
    EXPECT_NEAR(surface.positions[2], 0.039, 1e-7); // the north pole, float32
    for (int i = 0; i < 60; ++i)
        ASSERT_FALSE(s.step().rolled_back);
    std::vector<float> now;
    s.surface_positions(now);
    ASSERT_EQ(now.size(), 3 * nv);
    const double pole_sag = 0.039 - now[2];
    EXPECT_GT(pole_sag, 1e-4); // 10 kPa, 4 cm of tissue under gravity: ~mm
    EXPECT_NEAR(pole_sag, -s.probe_displacement("top").z(), 0.2 * pole_sag);
}

TEST(SimEmbedded, ContactSamplesTheEmbeddedSurface) {
    // The block free above a table, the sphere embedded: the block's own surface is not
    // sampled, the sphere is, so the block sinks into the table until the sphere's bottom
    // carries the weight (1 %).
    const std::string path = sphere_off(Vec3(0, 0, 0.02), 0.019, 24, 48);
    sim::Simulation s(scene::parse_scene(block_text(path, "hex", R"(,
      "loads": {"gravity": [0, 0, -9.81]},
      "obstacles": [{"type": "plane", "point": [0, 0, -0.0005], "normal": [0, 0, 1]}],
      "contact": {"stiffness": 1e7})")));
    for (int i = 0; i < 180; ++i)
        ASSERT_FALSE(s.step().rolled_back);
    const double weight = 1000 * 0.04 * 0.04 * 0.04 * 9.81;
    ASSERT_EQ(s.contact_reactions().size(), 1u);
    EXPECT_NEAR(s.contact_reactions()[0].force.z(), -weight, 0.01 * weight);
    // The block's corners went below the table: only the sphere touches it.
    double lowest = 1;
    for (const Vec3& p : s.positions())
        lowest = std::min(lowest, p.z());
    EXPECT_LT(lowest, -0.001);
}

namespace {
/// Directed edges of the triangles that do not appear exactly once with their reverse once.
int open_edges(const std::vector<std::uint32_t>& tri) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
    for (std::size_t t = 0; t < tri.size(); t += 3)
        for (int k = 0; k < 3; ++k)
            ++count[{ tri[t + std::size_t(k)], tri[t + std::size_t((k + 1) % 3)] }];
    int bad = 0;
    for (const auto& [e, n] : count) {
        const auto it = count.find({ e.second, e.first });
        bad += n != 1 || it == count.end() || it->second != 1;
    }
    return bad;
}
/// The edges open_edges() counts, with their ends' positions and the tag of a triangle at each.
std::string describe_open_edges(const sim::Surface& s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> at;
    for (std::size_t t = 0; t < s.triangles.size() / 3; ++t)
        for (int k = 0; k < 3; ++k)
            at[{ s.triangles[3 * t + std::size_t(k)],
                   s.triangles[3 * t + std::size_t((k + 1) % 3)] }]
                .push_back(t);
    std::string out;
    for (const auto& [e, ts] : at) {
        const auto it = at.find({ e.second, e.first });
        if (ts.size() == 1 && it != at.end() && it->second.size() == 1)
            continue;
        char line[256];
        const float* a = &s.positions[3 * e.first];
        const float* b = &s.positions[3 * e.second];
        std::snprintf(line, sizeof line, "%u-%u (%.7g %.7g %.7g)-(%.7g %.7g %.7g) x%zu tag %d\n",
            e.first, e.second, a[0], a[1], a[2], b[0], b[1], b[2], ts.size(),
            int(s.tags[ts.front()]));
        out += line;
    }
    return out;
}
} // namespace

TEST(SimEmbedded, ACutSplitsTheSkinAndClosesItWithDetailedLips) {
    // A vertical cut through the top half of the block: the embedded skin is split along the
    // blade (more skin triangles, no triangle across the cut) and closed by lips (tag 2) in the
    // cut plane, so the surface handed out is closed and oriented before and after the cut
    // opens under gravity; the split touched only the triangles near the cut.
    const std::string path = sphere_off(Vec3(0, 0, 0.02), 0.019, 24, 48);
    sim::Simulation s(scene::parse_scene(block_text(path, "mvc", R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
      "loads": {"gravity": [0, 0, -9.81]})")));
    const sim::Surface before = s.surface();
    const std::size_t skin = before.tags.size();
    EXPECT_EQ(open_edges(before.triangles), 0);
    const sim::CutSummary cut
        = s.cut({ { Vec3(-0.03, 0.001, 0.05), Vec3(0.03, 0.001, 0.05), Vec3(-0.03, 0.001, 0.021) },
            { Vec3(0.03, 0.001, 0.05), Vec3(0.03, 0.001, 0.021), Vec3(-0.03, 0.001, 0.021) } });
    ASSERT_TRUE(cut.ok()) << cut.reason;
    const sim::EmbeddedStats st = s.embedded_stats();
    EXPECT_TRUE(st.split);
    EXPECT_FALSE(st.full);
    EXPECT_GT(st.patch_triangles, 0u);
    EXPECT_LT(st.patch_triangles, skin / 2);
    const sim::Surface after = s.surface();
    EXPECT_GT(after.topology_version, before.topology_version);
    std::size_t skin_after = 0, lips = 0;
    for (const auto tag : after.tags)
        (tag == 1 ? skin_after : lips) += 1;
    EXPECT_GT(skin_after, skin);
    EXPECT_GT(lips, 0u);
    EXPECT_EQ(lips, st.lip_triangles);
    EXPECT_EQ(open_edges(after.triangles), 0);
    for (std::size_t t = 0; t < after.tags.size(); ++t) {
        if (after.tags[t] != 2)
            continue;
        for (int k = 0; k < 3; ++k) // at rest: the lips lie in the cut plane (float32)
            ASSERT_NEAR(
                after.positions[3 * after.triangles[3 * t + std::size_t(k)] + 1], 0.001, 1e-7);
    }
    for (int i = 0; i < 30; ++i)
        ASSERT_FALSE(s.step().rolled_back);
    const sim::Surface opened = s.surface();
    EXPECT_EQ(opened.topology_version, after.topology_version);
    EXPECT_EQ(opened.triangles, after.triangles);
    for (const float x : opened.positions)
        ASSERT_TRUE(std::isfinite(x));
    // The two lips part at the top (the halves sag apart under gravity): some lip vertices
    // that coincided at rest are now apart.
    std::map<std::array<float, 3>, std::size_t> first;
    double gap = 0;
    for (std::size_t v = 0; v < after.positions.size() / 3; ++v) {
        const std::array<float, 3> p { after.positions[3 * v], after.positions[3 * v + 1],
            after.positions[3 * v + 2] };
        const auto [it, fresh] = first.emplace(p, v);
        if (!fresh)
            for (int k = 0; k < 3; ++k)
                gap = std::max(gap,
                    double(std::abs(opened.positions[3 * v + std::size_t(k)]
                        - opened.positions[3 * it->second + std::size_t(k)])));
    }
    EXPECT_GT(gap, 1e-6);
}

class SimEmbeddedStroke : public ::testing::TestWithParam<std::string> { };

TEST_P(SimEmbeddedStroke, AStrokeOverTicksKeepsTheSurfaceClosed) {
    // The blade drawn across the block in 8 sweeps, one per tick, as the server applies a
    // scalpel: after every tick the surface is closed and oriented; reset() embeds it anew.
    const std::string path = sphere_off(Vec3(0, 0, 0.02), 0.019, 24, 48);
    sim::Simulation s(scene::parse_scene(block_text(path, GetParam(), R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}])")));
    const Vec3 down(0, 0, -0.03);
    auto at = [](int k) { return Vec3(-0.025 + 0.05 * k / 8, 0.0015, 0.045); };
    int applied = 0;
    for (int k = 0; k < 8; ++k) {
        const Vec3 a = at(k), b = at(k + 1);
        const sim::CutSummary c = s.cut({ { a, a + down, b }, { b, a + down, b + down } });
        applied += c.status == sim::CutSummary::Status::Applied;
        ASSERT_FALSE(s.step().rolled_back) << k;
        const sim::Surface now = s.surface();
        ASSERT_EQ(open_edges(now.triangles), 0) << "after sweep " << k << "\n"
                                                << describe_open_edges(now);
        EXPECT_TRUE(s.embedded_stats().split);
    }
    s.end_stroke();
    ASSERT_FALSE(s.step().rolled_back);
    EXPECT_EQ(open_edges(s.surface().triangles), 0);
    EXPECT_GT(applied, 4);
    EXPECT_GT(s.embedded_stats().lip_triangles, 0u);
}

INSTANTIATE_TEST_SUITE_P(SimEmbedded, SimEmbeddedStroke, ::testing::Values("mvc", "dg"),
    [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });
