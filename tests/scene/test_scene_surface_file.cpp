// CGAL-meshed scene geometry through sim::build_mesh (issue 18): the scene's repair, components
// and optimiser keys reach the meshing, its report comes back as sim::MeshingSummary, and a
// meshing error points at the scene key it is about.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/build_mesh.hpp"
#include "polycut/sim/simulation.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

using namespace polycut;
using namespace polycut::scene;

namespace {
const std::string kDefects = std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/liver_defects.off";

/// The defective organ surface (10 x 6.4 x 4.4 cm) at a coarse 1 cm cell size.
Scene organ(Repair repair = Repair::Auto) {
    Scene s;
    s.geometry.kind = Geometry::Kind::SurfaceFile;
    s.geometry.path = kDefects;
    s.geometry.cell_size = 0.01;
    s.geometry.seed = 0;
    s.geometry.repair = repair;
    return s;
}

/// JSON pointer of the SceneError build_mesh throws ("" if none).
std::string error_pointer(const Scene& s) {
    try {
        sim::build_mesh(s);
    } catch (const SceneError& e) {
        return e.where();
    }
    return "";
}
} // namespace

TEST(SceneSurfaceFile, RepairedOrganReportsRepairAndQuality) {
    sim::MeshingSummary m;
    const mesh::Mesh mesh = sim::build_mesh(organ(), &m);
    ASSERT_TRUE(m.meshed);
    EXPECT_EQ(m.source, "surface_file");
    ASSERT_TRUE(m.has_repair);
    EXPECT_EQ(m.repair_mode, "auto");
    EXPECT_EQ(m.repair_applied, "pmp"); // the defects of liver_defects.off are all PMP's
    EXPECT_FALSE(m.wrapped);
    EXPECT_EQ(m.holes_filled, 1);
    EXPECT_GT(m.self_intersections_in, 0);
    EXPECT_EQ(m.self_intersections_out, 0);
    EXPECT_EQ(m.components_out, 1);
    EXPECT_FALSE(m.repair_summary.empty());
    // PMP keeps the surface: the volume changes by the hole's filling (volume_in of an open
    // surface is an estimate). Mesh_3's boundary facets are chords within the facet distance
    // (cell_size / 10 = 1 mm) of a surface ~4 cm thick, so the tets hold a few per cent less.
    EXPECT_LT(std::abs(m.volume_change), 0.01);
    EXPECT_NEAR(m.volume_out / m.volume_in - 1, m.volume_change, 1e-12);
    EXPECT_NEAR(mesh.rest_volume() / m.volume_out, 0.96, 0.03);
    // Quality of what was built, with perturb and exude on by default.
    EXPECT_EQ(m.tets, mesh.num_cells());
    EXPECT_GT(m.min_dihedral_deg, 5.0);
    EXPECT_LT(m.max_dihedral_deg, 180.0);
    EXPECT_EQ(m.slivers, 0);
    EXPECT_FALSE(m.has_slivers);
    EXPECT_LE(m.radius_ratio_min, m.radius_ratio_p1);
    EXPECT_LE(m.radius_ratio_p1, m.radius_ratio_p50);
    EXPECT_LE(m.radius_ratio_p50, 1.0);
    EXPECT_GT(m.radius_ratio_min, 0.0);
    EXPECT_FALSE(m.quality_summary.empty());
    EXPECT_GT(m.mesh_ms, 0.0);
    EXPECT_GE(m.total_ms, m.mesh_ms + m.repair_ms);
}

TEST(SceneSurfaceFile, ScaleAppliesBeforeTheRepairAndMeshing) {
    // scale multiplies the file's positions before the repair and Mesh_3; the scene's cell
    // size stays in metres.
    Scene s = organ(Repair::Pmp);
    sim::MeshingSummary metres;
    const mesh::Mesh a = sim::build_mesh(s, &metres);
    s.geometry.scale = 2.0; // twice as large, same cell size: ~8x the volume
    sim::MeshingSummary doubled;
    const mesh::Mesh b = sim::build_mesh(s, &doubled);
    EXPECT_NEAR(doubled.volume_out / metres.volume_out, 8.0, 1e-9);
    EXPECT_NEAR(b.rest_volume() / a.rest_volume(), 8.0, 0.25);
    EXPECT_GT(b.num_cells(), 4 * a.num_cells());
}

TEST(SceneSurfaceFile, RepairNoneRefusesTheDefectiveSurface) {
    try {
        sim::build_mesh(organ(Repair::None));
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.where(), "/geometry/path");
        EXPECT_NE(e.problem().find("wrap"), std::string::npos) << e.what(); // suggests a mode
    }
}

TEST(SceneSurfaceFile, MeshingErrorsPointAtTheSceneKey) {
    // repair and components are enums: a Scene built in code cannot name an unknown mode
    Scene s = organ();
    s.geometry.optimize = { "smooth" };
    EXPECT_EQ(error_pointer(s), "/geometry/optimize");
    s = organ();
    s.geometry.sliver_bound = 75; // meshing::check_options: [0, 60) deg
    EXPECT_EQ(error_pointer(s), "/geometry/sliver_bound");
    s = organ();
    s.geometry.path = std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/missing.off";
    EXPECT_THROW(sim::build_mesh(s), FileError);
}

TEST(SceneSurfaceFile, ImplicitShapeReportsQualityWithoutRepair) {
    Scene s;
    s.geometry.kind = Geometry::Kind::Implicit;
    s.geometry.shape = Shape::Sphere;
    s.geometry.radii = Vec3::Constant(0.03);
    s.geometry.cell_size = 0.01;
    sim::MeshingSummary m;
    const mesh::Mesh mesh = sim::build_mesh(s, &m);
    ASSERT_TRUE(m.meshed);
    EXPECT_EQ(m.source, "implicit");
    EXPECT_FALSE(m.has_repair);
    EXPECT_EQ(m.tets, mesh.num_cells());
    EXPECT_GT(m.min_dihedral_deg, 5.0);
    EXPECT_GT(m.mesh_ms, 0.0);
    // Chords within the facet distance (1 mm) of a 3 cm sphere: up to 3 x 1/30 less volume.
    EXPECT_NEAR(mesh.rest_volume() / (4.0 / 3.0 * std::numbers::pi * 2.7e-5), 0.95, 0.05);
}

TEST(SceneSurfaceFile, BoxIsNotMeshedByCgal) {
    Scene s; // the default geometry: a box grid
    sim::MeshingSummary m;
    m.meshed = true; // overwritten
    sim::build_mesh(s, &m);
    EXPECT_FALSE(m.meshed);
    EXPECT_EQ(m.tets, 0);
}
