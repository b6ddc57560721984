#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"

#include <filesystem>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::scene;

namespace {
const char* kMinimal = R"({
  "name": "block",
  "geometry": {"type": "box", "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4]},
  "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.45, "density": 1000},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
  "loads": {"gravity": [0, 0, -9.81]},
  "probes": [{"name": "top", "point": [0.05, 0.05, 0.1]}]
})";

// Parses text and returns the JSON pointer of the SceneError it throws ("" if none).
std::string error_pointer(const std::string& text) {
    try {
        parse_scene(text);
    } catch (const SceneError& e) {
        return e.where();
    }
    return "";
}

std::string with(const std::string& from, const std::string& to) {
    std::string s = kMinimal;
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
}
} // namespace

TEST(Scene, MinimalSceneGetsDefaults) {
    const Scene s = parse_scene(kMinimal);
    EXPECT_EQ(s.name, "block");
    EXPECT_EQ(s.method, Method::Tet);
    EXPECT_EQ(s.geometry.cells, Eigen::Vector3i(4, 4, 4));
    EXPECT_DOUBLE_EQ(s.material.poisson_ratio, 0.45);
    EXPECT_EQ(s.integrator.type, integrate::IntegratorKind::ImplicitEuler);
    ASSERT_EQ(s.fixed.size(), 1u);
    EXPECT_TRUE(selects(s.fixed[0].where, Vec3(0.03, 0.02, 0.0)));
    EXPECT_FALSE(selects(s.fixed[0].where, Vec3(0.03, 0.02, 0.001)));
    EXPECT_DOUBLE_EQ(s.loads.gravity.z(), -9.81);
    ASSERT_EQ(s.probes.size(), 1u);
}

TEST(Scene, ErrorsPointAtTheField) {
    EXPECT_EQ(error_pointer(with("\"poisson_ratio\": 0.45", "\"poisson_ratio\": 0.5")),
        "/material/poisson_ratio");
    EXPECT_EQ(error_pointer(with("\"poisson_ratio\": 0.45", "\"poisson_ratio\": \"soft\"")),
        "/material/poisson_ratio");
    EXPECT_EQ(error_pointer(with("\"youngs_modulus\": 1e4", "\"youngs_modulus\": -3")),
        "/material/youngs_modulus");
    EXPECT_EQ(error_pointer(with("\"density\": 1000", "\"density\": 1000, \"colour\": 1")),
        "/material/colour");
    EXPECT_EQ(
        error_pointer(with("\"cells\": [4, 4, 4]", "\"cells\": [4, 0, 4]")), "/geometry/cells/1");
    EXPECT_EQ(
        error_pointer(with("\"size\": [0.1, 0.1, 0.1]", "\"size\": [0.1, 0.1]")), "/geometry/size");
    EXPECT_EQ(error_pointer(with("\"normal\": [0, 0, 1]", "\"normal\": [0, 0, 0]")),
        "/fixed/0/plane/normal");
    EXPECT_EQ(error_pointer(with("\"point\": [0.05, 0.05, 0.1]", "\"point\": [0.05, null, 0.1]")),
        "/probes/0/point/1");
    EXPECT_EQ(error_pointer(with("\"type\": \"box\"", "\"type\": \"cube\"")), "/geometry/type");
    EXPECT_EQ(error_pointer(with("\"name\": \"block\",", "")), "/name");
    EXPECT_EQ(error_pointer(with("\"name\": \"block\",", "\"name\": \"block\", \"extra\": {},")),
        "/extra");
    EXPECT_EQ(error_pointer("{\"name\": "), "/");
    EXPECT_EQ(error_pointer("[1, 2]"), "/");
}

TEST(Scene, MessagesSayWhatIsAllowed) {
    try {
        parse_scene(with("\"poisson_ratio\": 0.45", "\"poisson_ratio\": 0.7"));
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("must be in [-0.999, 0.4999]"), std::string::npos)
            << e.what();
    }
    try {
        parse_scene(with("\"density\": 1000", "\"density\": 1000, \"colour\": 1"));
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown key"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("youngs_modulus"), std::string::npos) << e.what();
    }
}

TEST(Scene, LoadsAndSweepsParse) {
    const std::string text = with("\"loads\": {\"gravity\": [0, 0, -9.81]}",
        R"("loads": {"forces": [{"plane": {"point": [0.1, 0, 0], "normal": [1, 0, 0]},
             "force": [0, 0, -3]}, {"probe": "top", "force": [1, 0, 0]}]},
           "cutting": {"sweeps": [{"tick": 3, "triangles": [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]}]})");
    const Scene s = parse_scene(text);
    ASSERT_EQ(s.loads.forces.size(), 2u);
    EXPECT_EQ(s.loads.forces[0].kind, Force::Kind::Region);
    EXPECT_EQ(s.loads.forces[1].probe, "top");
    ASSERT_EQ(s.cutting.sweeps.size(), 1u);
    EXPECT_EQ(s.cutting.sweeps[0].tick, 3);
    EXPECT_EQ(error_pointer(with("\"loads\": {\"gravity\": [0, 0, -9.81]}",
                  R"("loads": {"forces": [{"probe": "nowhere", "force": [0, 0, 1]}]})")),
        "/loads/forces/0/probe");
}

TEST(Scene, SolverWarmStartParses) {
    EXPECT_EQ(parse_scene(kMinimal).solver.warm_start, WarmStart::Previous);
    const std::string loads = "\"loads\": {\"gravity\": [0, 0, -9.81]}";
    const Scene s = parse_scene(with(
        loads, loads + R"(, "solver": {"preconditioner": "amg", "warm_start": "extrapolated"})"));
    EXPECT_EQ(s.solver.warm_start, WarmStart::Extrapolated);
    EXPECT_EQ(s.solver.refactor_iterations, 50);
    EXPECT_EQ(parse_scene(with(loads, loads + R"(, "solver": {"refactor_iterations": 10})"))
                  .solver.refactor_iterations,
        10);
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"refactor_iterations": -1})")),
        "/solver/refactor_iterations");
    EXPECT_EQ(s.solver.preconditioner, Preconditioner::Amg);
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"warm_start": "linear"})")),
        "/solver/warm_start");
    EXPECT_EQ(s.solver.start_vectors, 4);
    const Scene p = parse_scene(
        with(loads, loads + R"(, "solver": {"warm_start": "projected", "start_vectors": 6})"));
    EXPECT_EQ(p.solver.warm_start, WarmStart::Projected);
    EXPECT_EQ(p.solver.start_vectors, 6);
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"start_vectors": 0})")),
        "/solver/start_vectors");
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"start_vectors": 33})")),
        "/solver/start_vectors");
}

TEST(Scene, ThreadsAndAmgOptionsParse) {
    // issue 18: integrator.threads, solver.amg; defaults are the serial run and AmgOptions'
    const Scene d = parse_scene(kMinimal);
    EXPECT_EQ(d.integrator.threads, 1);
    EXPECT_DOUBLE_EQ(d.solver.amg_strong_threshold, 0.5);
    EXPECT_FALSE(d.solver.amg_rigid_body_modes);
    const std::string loads = "\"loads\": {\"gravity\": [0, 0, -9.81]}";
    const Scene s = parse_scene(with(loads, loads + R"(, "integrator": {"threads": 2},
        "solver": {"preconditioner": "amg", "amg": {"strong_threshold": 0.25,
        "aggressive_levels": 0, "interpolation_max_elements": 6, "rigid_body_modes": true}})"));
    EXPECT_EQ(s.integrator.threads, 2);
    EXPECT_DOUBLE_EQ(s.solver.amg_strong_threshold, 0.25);
    EXPECT_EQ(s.solver.amg_aggressive_levels, 0);
    EXPECT_EQ(s.solver.amg_interpolation_max_elements, 6);
    EXPECT_TRUE(s.solver.amg_rigid_body_modes);
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "integrator": {"threads": 0})")),
        "/integrator/threads");
    EXPECT_EQ(d.integrator.stiffness_every, 1);
    EXPECT_EQ(parse_scene(with(loads, loads + R"(, "integrator": {"stiffness_every": 4})"))
                  .integrator.stiffness_every,
        4);
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "integrator": {"stiffness_every": 0})")),
        "/integrator/stiffness_every");
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"amg": {"strong_threshold": 0}})")),
        "/solver/amg/strong_threshold");
    EXPECT_EQ(error_pointer(with(loads, loads + R"(, "solver": {"amg": {"theta": 0.5}})")),
        "/solver/amg/theta");
}

TEST(Scene, EveryShippedSceneParses) {
    const std::filesystem::path dir = std::filesystem::path(POLYCUT_SOURCE_DIR) / "assets/scenes";
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".json")
            continue;
        SCOPED_TRACE(entry.path().string());
        EXPECT_NO_THROW(load_scene(entry.path().string()));
        ++count;
    }
    EXPECT_GT(count, 0);
}

// Issue 17: pressure loads, the hollow sphere, boxes given by corners, single-node supports and
// the mean-dilatation element; each with the error that points at its field.
TEST(Scene, PressureCornersHollowSphereNodeSupportsAndVolumetricParse) {
    const Scene s = parse_scene(with(R"("loads": {"gravity": [0, 0, -9.81]})",
        R"("loads": {"pressure": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "pressure": 250}]},
           "basis": {"volumetric": "mean_dilatation"})"));
    ASSERT_EQ(s.loads.pressures.size(), 1u);
    EXPECT_DOUBLE_EQ(s.loads.pressures[0].pressure, 250);
    EXPECT_EQ(s.basis.volumetric, basis::VolumetricRule::MeanDilatation);
    EXPECT_EQ(parse_scene(kMinimal).basis.volumetric, basis::VolumetricRule::Full);
    EXPECT_EQ(error_pointer(with(R"("loads": {"gravity": [0, 0, -9.81]})",
                  R"("loads": {"pressure": [{"pressure": 1}]})")),
        "/loads/pressure/0");
    EXPECT_EQ(
        error_pointer(with(R"("loads": {)", R"("basis": {"volumetric": "bbar"}, "loads": {)")),
        "/basis/volumetric");

    const Scene c = parse_scene(with(R"("size": [0.1, 0.1, 0.1])",
        R"("corners": [[0,0,0],[48,44,0],[48,60,0],[0,44,0],[0,0,1],[48,44,1],[48,60,1],[0,44,1]])"));
    ASSERT_EQ(c.geometry.corners.size(), 8u);
    EXPECT_EQ(c.geometry.corners[2], Vec3(48, 60, 0));
    EXPECT_EQ(error_pointer(with(R"("size": [0.1, 0.1, 0.1])",
                  R"("size": [0.1, 0.1, 0.1], "corners": [[0,0,0]])")),
        "/geometry/corners");

    const std::string hollow = R"("geometry": {"type": "implicit", "shape": "hollow_sphere",
        "radius": 0.04, "inner_radius": 0.02, "cell_size": 0.005})";
    const Scene h = parse_scene(with(
        R"("geometry": {"type": "box", "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4]})", hollow));
    EXPECT_EQ(h.geometry.shape, Shape::HollowSphere);
    EXPECT_DOUBLE_EQ(h.geometry.inner_radius, 0.02);
    EXPECT_EQ(error_pointer(with(
                  R"("geometry": {"type": "box", "size": [0.1, 0.1, 0.1], "cells": [4, 4, 4]})",
                  R"("geometry": {"type": "implicit", "shape": "hollow_sphere", "radius": 0.04,
                      "inner_radius": 0.05, "cell_size": 0.005})")),
        "/geometry/inner_radius");

    const Scene n = parse_scene(with(R"({"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}})",
        R"({"node": [0.1, 0, 0], "components": "yz"})"));
    ASSERT_EQ(n.fixed.size(), 1u);
    EXPECT_TRUE(n.fixed[0].at_node);
    EXPECT_EQ(n.fixed[0].node, Vec3(0.1, 0, 0));
    EXPECT_FALSE(n.fixed[0].components[0]);
    EXPECT_EQ(error_pointer(with(R"({"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}})",
                  R"({"node": [0, 0, 0], "box": {"min": [0, 0, 0], "max": [1, 1, 1]}})")),
        "/fixed/0/node");
}
