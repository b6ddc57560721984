// The embedded surface through the facade (issue 15 item 2): the surface the simulation hands
// out (stream, renderer) is the embedded one, it follows the tissue, contact samples it, and
// after a cut it is embedded in the cut mesh with the lips (tag 2) streamed beside it.
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

using namespace polycut;

namespace {
/// A UV sphere of radius r about c as an OFF file in the temp directory; returns its path.
std::string sphere_off(const Vec3& c, double r, int rings, int segments) {
    constexpr double pi = 3.14159265358979323846;
    std::vector<Vec3> v { c + Vec3(0, 0, r) };
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double th = pi * i / rings, ph = 2 * pi * j / segments;
            v.push_back(c
                + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
        }
    v.push_back(c - Vec3(0, 0, r));
    const int south = int(v.size()) - 1;
    auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
    std::vector<std::array<int, 3>> t;
    for (int j = 0; j < segments; ++j) {
        t.push_back({ 0, ring(1, j), ring(1, j + 1) });
        t.push_back({ south, ring(rings - 1, j + 1), ring(rings - 1, j) });
        for (int i = 1; i + 1 < rings; ++i) {
            t.push_back({ ring(i, j), ring(i + 1, j), ring(i + 1, j + 1) });
            t.push_back({ ring(i, j), ring(i + 1, j + 1), ring(i, j + 1) });
        }
    }
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

TEST(SimEmbedded, ACutReembedsAndStreamsTheLips) {
    // A vertical cut through the top half of the block: the embedded skin keeps its triangles
    // (not split: its vertices follow the piece their rest position lies in), and the lips of
    // the cut mesh come with it as tag-2 triangles, closed over both sides.
    const std::string path = sphere_off(Vec3(0, 0, 0.02), 0.019, 24, 48);
    sim::Simulation s(scene::parse_scene(block_text(path, "mvc", R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}])")));
    const std::size_t skin = s.surface().tags.size();
    const sim::CutSummary cut
        = s.cut({ { Vec3(-0.03, 0.001, 0.05), Vec3(0.03, 0.001, 0.05), Vec3(-0.03, 0.001, 0.021) },
            { Vec3(0.03, 0.001, 0.05), Vec3(0.03, 0.001, 0.021), Vec3(-0.03, 0.001, 0.021) } });
    ASSERT_TRUE(cut.ok()) << cut.reason;
    ASSERT_FALSE(s.step().rolled_back);
    const sim::Surface after = s.surface();
    std::size_t skin_after = 0, lips = 0;
    for (const auto tag : after.tags)
        (tag == 1 ? skin_after : lips) += 1;
    EXPECT_EQ(skin_after, skin);
    EXPECT_GT(lips, 0u);
    for (const float x : after.positions)
        ASSERT_TRUE(std::isfinite(x));
}
