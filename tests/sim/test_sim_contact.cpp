// Contact through the facade (issue 15 item 1): a block resting on a table obstacle carries its
// weight, a probe tool pressing the tissue gets a reaction that grows with depth and acts
// through its centre, a spatula pushes the lips of a cut apart, bad obstacles and tools are
// refused with their field named.
#include "polycut/common/error.hpp"
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;

namespace {
sim::Simulation make(const std::string& text) {
    return sim::Simulation(scene::parse_scene(text, POLYCUT_SOURCE_DIR "/assets/scenes"));
}

const sim::BodyReaction* reaction(const sim::Simulation& s, const std::string& kind, long id) {
    for (const auto& r : s.contact_reactions())
        if (r.kind == kind && r.id == id)
            return &r;
    return nullptr;
}

/// A 4 x 4 x 2 cm hex block of `cells` x `cells` x `cells` / 2 hexes; `extra` adds keys.
std::string block(const std::string& extra, const std::string& integrator, int cells = 4) {
    const std::string n = std::to_string(cells), half = std::to_string(cells / 2);
    return R"({"name": "block",
      "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
                   "cells": [)"
        + n + ", " + n + ", " + half + R"(], "elements": "hex"},
      "method": "hex",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000,
                   "rayleigh_mass": 8, "rayleigh_stiffness": 0.01},
      "integrator": )"
        + integrator + R"(,
      "solver": {"type": "cholmod"})"
        + extra + "}";
}
} // namespace

TEST(SimContact, BlockOnTheTableCarriesItsWeight) {
    // A free block 1 mm above a table (a plane obstacle, and a box obstacle under it that it
    // never reaches): after 3 s at 60 Hz the table carries m g (0.5 %), the box nothing.
    sim::Simulation s = make(block(R"(,
      "loads": {"gravity": [0, 0, -9.81]},
      "obstacles": [{"type": "plane", "name": "table", "point": [0, 0, -0.001], "normal": [0, 0, 1]},
                    {"type": "box", "center": [0, 0, -0.05], "size": [0.1, 0.1, 0.02]}],
      "contact": {"stiffness": 1e7})",
        R"({"type": "implicit_euler", "dt": 0.0166667})"));
    for (int i = 0; i < 180; ++i)
        ASSERT_FALSE(s.step().rolled_back) << i;
    const double weight = 1000 * 0.04 * 0.04 * 0.02 * 9.81;
    const sim::BodyReaction* table = reaction(s, "obstacle", 0);
    ASSERT_NE(table, nullptr);
    EXPECT_EQ(table->name, "table");
    EXPECT_NEAR(table->force.z(), -weight, 5e-3 * weight);
    EXPECT_GT(table->points, 0);
    EXPECT_LT(table->max_depth, 1e-3);
    const sim::BodyReaction* box = reaction(s, "obstacle", 1);
    ASSERT_NE(box, nullptr);
    EXPECT_EQ(box->points, 0);
    EXPECT_EQ(box->force, Vec3::Zero());
}

TEST(SimContact, ProbePressesTheTissueAndFeelsItPushBack) {
    // An 8 mm probe pressed into the top of a block of 5 mm hexes fixed at its base, 0.5 mm
    // per tick to 3 mm, then held: the reaction on the probe points up, grows with the depth,
    // and (a ball's penalty forces are all radial) has no torque about its centre; by symmetry
    // of the hex grid about the probe's axis it has no lateral part. (On 1 cm cells a ball
    // this size touches one node, which slides off its bottom: sample the surface finer than
    // the tool, or embed a fine surface, docs/decisions/0030.)
    sim::Simulation s = make(block(R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}])",
        R"({"type": "implicit_euler", "dt": 0.0166667})", 8));
    sim::ToolSpec probe;
    probe.kind = sim::ToolSpec::Kind::Sphere;
    probe.radius = 0.008;
    probe.pose.position = Vec3(0, 0, 0.028);
    probe.stiffness = 1e8;
    const long id = s.add_tool(probe);
    EXPECT_EQ(s.tool_count(), 1u);
    double last = 0;
    for (int k = 1; k <= 6; ++k) {
        sim::ToolPose pose;
        pose.position = Vec3(0, 0, 0.028 - 0.0005 * k);
        ASSERT_TRUE(s.move_tool(id, pose));
        ASSERT_FALSE(s.step().rolled_back);
    }
    for (int i = 0; i < 120; ++i) {
        ASSERT_FALSE(s.step().rolled_back);
        if (i == 60)
            last = reaction(s, "tool", id)->force.z();
    }
    ASSERT_NE(reaction(s, "tool", id), nullptr);
    const sim::BodyReaction r = *reaction(s, "tool", id); // a copy: the next step refills them
    EXPECT_GT(r.force.z(), 0.01); // a 3 mm dent in 10 kPa tissue: tenths of a newton
    EXPECT_NEAR(r.force.z(), last, 1e-3 * r.force.z()); // settled
    EXPECT_LT(r.force.head<2>().norm(), 1e-6 * r.force.z());
    EXPECT_LT(r.torque.norm(), 1e-9 * r.force.z());
    // Deeper (to 6 mm, 0.5 mm per tick: node samples 1 cm apart see a 5 mm ball only while
    // it moves less than its radius past them), more force.
    for (int k = 7; k <= 12; ++k) {
        sim::ToolPose pose;
        pose.position = Vec3(0, 0, 0.028 - 0.0005 * k);
        s.move_tool(id, pose);
        ASSERT_FALSE(s.step().rolled_back);
    }
    for (int i = 0; i < 120; ++i)
        ASSERT_FALSE(s.step().rolled_back);
    EXPECT_GT(reaction(s, "tool", id)->force.z(), 1.5 * r.force.z());
    EXPECT_TRUE(s.remove_tool(id));
    EXPECT_FALSE(s.remove_tool(id));
    s.step();
    EXPECT_TRUE(s.contact_reactions().empty());
}

TEST(SimContact, SpatulaPressesTheLipsOfACutApart) {
    // A vertical cut through the top half of the block along y = 0, then a 2 mm thick blade
    // lowered into it: both lips are pushed out of the blade (each side by about half its
    // thickness), so the incision opens to nearly the blade's thickness.
    sim::Simulation s = make(block(R"(,
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}])",
        R"({"type": "implicit_euler", "dt": 0.0166667})"));
    const double y = 0, top = 0.03, depth = 0.011;
    const sim::CutSummary cut
        = s.cut({ { Vec3(-0.03, y, top), Vec3(0.03, y, top), Vec3(-0.03, y, depth) },
            { Vec3(0.03, y, top), Vec3(0.03, y, depth), Vec3(-0.03, y, depth) } });
    ASSERT_TRUE(cut.ok()) << cut.reason;
    s.step();
    sim::ToolSpec blade;
    blade.kind = sim::ToolSpec::Kind::Blade;
    blade.size = Vec3(0.02, 0.002, 0.02); // x: length, y: thickness, z: height
    blade.pose.position = Vec3(0, 0, 0.035);
    blade.stiffness = 1e8;
    const long id = s.add_tool(blade);
    for (int k = 1; k <= 20; ++k) {
        sim::ToolPose pose;
        pose.position = Vec3(0, 0, 0.035 - 0.0005 * k); // down to 0.025: 5 mm into the cut
        s.move_tool(id, pose);
        ASSERT_FALSE(s.step().rolled_back) << k;
    }
    for (int i = 0; i < 60; ++i)
        ASSERT_FALSE(s.step().rolled_back);
    // The two copies of the lip node at (0, 0, 0.02): the nodes nearest it now, one per side.
    double left = 1, right = -1;
    for (const Vec3& p : s.positions())
        if (std::abs(p.x()) < 5e-4 && std::abs(p.z() - 0.02) < 1e-3 && std::abs(p.y()) < 0.003) {
            left = std::min(left, p.y());
            right = std::max(right, p.y());
        }
    EXPECT_LT(left, -0.0009);
    EXPECT_GT(right, 0.0009);
    EXPECT_GT(right - left, 0.0019); // the blade is 2 mm thick; the penalty lets it in slightly
    const sim::BodyReaction* r = reaction(s, "tool", id);
    ASSERT_NE(r, nullptr);
    EXPECT_GT(r->points, 0);
}

TEST(SimContact, BadObstaclesAndToolsAreRefusedWithTheirField) {
    try {
        make(block(R"(, "obstacles": [{"type": "cone", "point": [0, 0, 0]}])",
            R"({"type": "implicit_euler"})"));
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.where(), "/obstacles/0/type");
    }
    try {
        make(block(R"(, "obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}])",
            R"({"type": "implicit_euler"})"));
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.where(), "/obstacles/0/radius");
    }
    try {
        make(block(R"(, "obstacles": [{"type": "mesh", "path": "no_such.off"}])",
            R"({"type": "implicit_euler"})"));
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.where(), "/obstacles/0/path");
    }
    sim::Simulation s = make(block("", R"({"type": "implicit_euler"})"));
    sim::ToolSpec t;
    t.radius = std::nan("");
    try {
        s.add_tool(t);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.where(), "radius");
    }
    t.radius = 0.01;
    t.pose.orientation = Eigen::Quaterniond(0, 0, 0, 0);
    EXPECT_THROW(s.add_tool(t), InputError);
    EXPECT_EQ(s.tool_count(), 0u);
    EXPECT_FALSE(s.move_tool(42, sim::ToolPose {}));
}

TEST(SimContact, MeshObstacleFromASurfaceFile) {
    // The organ blob's surface as an obstacle (CGAL AABB tree): a small block dropped on top
    // of it comes to rest on it, held by it against gravity.
    sim::Simulation s = make(R"({"name": "on_organ",
      "geometry": {"type": "box", "origin": [-0.005, -0.005, 0.0212], "size": [0.01, 0.01, 0.005],
                   "cells": [2, 2, 1], "elements": "hex"},
      "method": "hex",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000, "rayleigh_mass": 8},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "cholmod"},
      "loads": {"gravity": [0, 0, -9.81]},
      "obstacles": [{"type": "mesh", "path": "../meshes/liver_blob.off", "scale": 1.0}],
      "contact": {"stiffness": 1e7, "friction": 0.8}})");
    for (int i = 0; i < 120; ++i)
        ASSERT_FALSE(s.step().rolled_back) << i;
    const double weight = 1000 * 0.01 * 0.01 * 0.005 * 9.81;
    const sim::BodyReaction* organ = reaction(s, "obstacle", 0);
    ASSERT_NE(organ, nullptr);
    EXPECT_GT(organ->points, 0);
    EXPECT_NEAR(organ->force.z(), -weight, 0.02 * weight);
}

TEST(SimContact, PiecesACutSeparatedPushEachOther) {
    // A block cut through along y = 0 into two pieces, both fixed at the base; a blade pushes
    // the -y piece's top 4 mm toward +y. Without self contact its lip sinks into the +y piece
    // (the two copies of the lip node at (0, 0, 0.02) part by 2.5 mm); with it, the +y piece
    // is pushed along (1.5 mm) and the copies stay within 0.2 mm (bound 0.5 mm).
    auto lip_gap = [](double self_stiffness, double& moved) {
        sim::Simulation s = make(block(R"(,
          "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
          "contact": {"self_stiffness": )"
                + std::to_string(self_stiffness) + "}",
            R"({"type": "implicit_euler", "dt": 0.0166667})"));
        const sim::CutSummary cut
            = s.cut({ { Vec3(-0.03, 0, 0.03), Vec3(0.03, 0, 0.03), Vec3(-0.03, 0, -0.01) },
                { Vec3(0.03, 0, 0.03), Vec3(0.03, 0, -0.01), Vec3(-0.03, 0, -0.01) } });
        EXPECT_TRUE(cut.ok()) << cut.reason;
        s.step();
        EXPECT_EQ(s.mesh_stats().components, 2);
        std::vector<std::size_t> lip;
        for (std::size_t i = 0; i < s.positions().size(); ++i)
            if ((s.positions()[i] - Vec3(0, 0, 0.02)).norm() < 1e-4)
                lip.push_back(i);
        EXPECT_EQ(lip.size(), 2u);
        sim::ToolSpec blade;
        blade.kind = sim::ToolSpec::Kind::Blade;
        blade.size = Vec3(0.05, 0.004, 0.012);
        blade.pose.position = Vec3(0, -0.0221, 0.02);
        blade.stiffness = 1e8;
        const long id = s.add_tool(blade);
        for (int k = 1; k <= 40; ++k) {
            sim::ToolPose pose;
            pose.position = Vec3(0, -0.0221 + 0.0001 * k, 0.02);
            s.move_tool(id, pose);
            EXPECT_FALSE(s.step().rolled_back);
        }
        for (int i = 0; i < 30; ++i)
            s.step();
        const double y0 = s.positions()[lip[0]].y(), y1 = s.positions()[lip[1]].y();
        moved = std::min(y0, y1);
        return std::abs(y0 - y1);
    };
    double moved_free = 0, moved_contact = 0;
    const double free_gap = lip_gap(0, moved_free);
    const double contact_gap = lip_gap(1e8, moved_contact);
    EXPECT_GT(free_gap, 1e-3); // the lip went into the other piece
    EXPECT_LT(contact_gap, 5e-4);
    EXPECT_GT(moved_contact, 5e-4); // both copies were pushed along
}
