// What a scene builds (issue 17 item 6, DESIGN.md sec. 6): sim::Simulation::build_report() says
// which parts a scene built and what they cost. A static scene builds no inertia, a scene that
// is not cut builds no cut structures, a tet scene builds no polyhedral bases; each claim is
// paired with the scene that does build the part, so the report is seen to change.
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <iterator>

using namespace polycut;

namespace {
std::string block(const std::string& method, const std::string& integrator,
    const std::string& geometry_extra = "") {
    const bool hex = method == "hex";
    return R"({"name": "block",
      "geometry": {"type": ")"
        + std::string(method == "mvc" ? "random_planes" : "box")
        + R"(", "size": [0.04, 0.04, 0.02], "cells": [4, 4, 2], "elements": ")"
        + (hex ? "hex" : "tet") + "\"" + geometry_extra + R"(},
      "method": ")"
        + method + R"(",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000},
      "integrator": )"
        + integrator + R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
      "loads": {"gravity": [0, 0, -9.81]}})";
}
const char* kStatic = R"({"type": "static"})";
const char* kDynamic = R"({"type": "implicit_euler", "dt": 0.01})";

sim::Simulation make(const std::string& text) {
    return sim::Simulation(scene::parse_scene(text));
}
} // namespace

TEST(BuildReport, StaticSceneBuildsNoInertia) {
    sim::Simulation stat = make(block("tet", kStatic));
    stat.step();
    stat.step();
    const sim::BuildReport r = stat.build_report();
    EXPECT_FALSE(r.detail("inertia").empty()); // the part is reported...
    EXPECT_FALSE(r.built("inertia")) << r.detail("inertia"); // ...and not built
    EXPECT_TRUE(r.built("model"));
    // the same block, dynamic: the inertia is made at the first step, not at load
    sim::Simulation dyn = make(block("tet", kDynamic));
    EXPECT_FALSE(dyn.build_report().built("inertia"));
    dyn.step();
    EXPECT_TRUE(dyn.build_report().built("inertia"));
}

TEST(BuildReport, SceneWithoutCuttingBuildsNoCutStructures) {
    sim::Simulation s = make(block("tet", kDynamic));
    for (int i = 0; i < 3; ++i)
        s.step();
    EXPECT_FALSE(s.build_report().built("cut"));
    EXPECT_FALSE(s.build_report().built("contact"));
    EXPECT_FALSE(s.build_report().built("embedded"));
    EXPECT_FALSE(s.build_report().built("octree"));
    // a cut through the middle of the block makes them
    const sim::CutSummary cut = s.cut(
        { { Vec3(0.021, -0.01, 0.03), Vec3(0.021, 0.05, 0.03), Vec3(0.021, 0.02, 0.005) } });
    EXPECT_EQ(cut.status, sim::CutSummary::Status::Applied) << cut.reason;
    EXPECT_TRUE(s.build_report().built("cut"));
}

TEST(BuildReport, TetSceneBuildsNoPolyhedralBases) {
    const sim::Simulation tet = make(block("tet", kStatic));
    const sim::BuildReport t = tet.build_report();
    EXPECT_EQ(t.p1_bases, long(tet.cell_count())); // 4 x 4 x 2 blocks, 6 tets each
    EXPECT_EQ(t.p1_bases, 4 * 4 * 2 * 6);
    EXPECT_EQ(t.q1_bases, 0);
    EXPECT_EQ(t.polyhedral_bases, 0);
    // hexes get Q1 and nothing else; a grid cut by random planes gets polyhedral bases
    const sim::Simulation hex = make(block("hex", kStatic));
    EXPECT_EQ(hex.build_report().q1_bases, 4 * 4 * 2);
    EXPECT_EQ(hex.build_report().polyhedral_bases + hex.build_report().p1_bases, 0);
    const sim::Simulation mvc = make(block("mvc", kStatic, R"(, "planes_per_cell": 2)"));
    const sim::BuildReport m = mvc.build_report();
    EXPECT_GT(m.polyhedral_bases, 0);
    EXPECT_EQ(m.p1_bases + m.q1_bases + m.polyhedral_bases, long(mvc.cell_count()));
}

TEST(BuildReport, PartsComeInBuildOrderWithTheirCosts) {
    const sim::Simulation s = make(block("tet", kDynamic));
    const sim::BuildReport r = s.build_report();
    const char* order[] = { "mesh", "model", "integrator", "contact", "surface", "embedded",
        "octree", "solver", "inertia", "cut" };
    ASSERT_EQ(r.parts.size(), std::size(order));
    for (std::size_t i = 0; i < r.parts.size(); ++i) {
        EXPECT_EQ(r.parts[i].name, order[i]);
        EXPECT_TRUE(std::isfinite(r.parts[i].ms) && r.parts[i].ms >= 0) << order[i];
        EXPECT_FALSE(r.parts[i].detail.empty()) << order[i];
    }
    EXPECT_NE(r.detail("mesh").find("192 cells"), std::string::npos) << r.detail("mesh");
    EXPECT_EQ(r.find("dg_model"), nullptr); // not a DG scene
}

TEST(BuildReport, CuttingPreparedAtLoadIsAPartWithItsCost) {
    // The server prepares the cut pipeline where it builds a scene (any client may cut it), so
    // the structures a headless run makes at the first cut are then a part built at load.
    sim::Simulation s = make(block("tet", kDynamic));
    s.prepare_cutting();
    s.prepare_cutting(); // a second call builds nothing more
    const sim::BuildReport r = s.build_report();
    ASSERT_TRUE(r.built("cut"));
    EXPECT_NE(r.detail("cut").find("prepared at load"), std::string::npos) << r.detail("cut");
    long entries = 0;
    for (const sim::BuildPart& p : r.parts)
        if (p.name == "cut") {
            ++entries;
            EXPECT_TRUE(std::isfinite(p.ms) && p.ms >= 0);
        }
    EXPECT_EQ(entries, 1);
    // reset() builds the scene again without it
    s.reset();
    EXPECT_FALSE(s.build_report().built("cut"));
}
