// Octree geometry through the facade (issue 15 item 3; 001 sec. 7-8): a box cantilever on an
// adaptive octree with polyhedral transition cells against the beam formula, an implicit organ
// embedded in an octree (coarse core, fine skin) with its detailed surface, stress-based 1-to-8
// refinement while it runs with the state carried over without a pop, and the scene's errors.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>

using namespace polycut;

namespace {
constexpr double kBeamTip = 8.64e-3; // 002 Table 3.1 [m]

/// The 002 sec. 3.3 cantilever (1.2 x 0.3 x 0.2 m, E = 1 MPa, nu = 0, -3 N on the free end) on
/// an octree of 0.1 m cells; `octree` adds keys to the geometry, `integrator` replaces the
/// static one.
std::string cantilever(const std::string& octree, const std::string& method = "harmonic",
    const std::string& integrator
    = R"({"type": "static", "corotated": false, "tolerance": 1e-8})") {
    return R"({"name": "octree_cantilever",
      "geometry": {"type": "octree", "origin": [0, 0, 0], "size": [1.2, 0.3, 0.2],
                   "cell_size": 0.1)"
        + octree + R"(},
      "method": ")"
        + method + R"(",
      "basis": {"rule": "reference", "gauss_degree": 2},
      "material": {"youngs_modulus": 1e6, "poisson_ratio": 0.0, "density": 1000},
      "integrator": )"
        + integrator + R"(,
      "solver": {"type": "cholmod"},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [1, 0, 0], "tolerance": 1e-9}}],
      "probes": [{"name": "tip", "point": [1.2, 0.15, 0.1]}],
      "loads": {"forces": [{"plane": {"point": [1.2, 0, 0], "normal": [1, 0, 0],
                "tolerance": 1e-9}, "distribution": "area", "force": [0, 0, -3]}]}})";
}

double tip_error(sim::Simulation& s) {
    const sim::StepReport r = s.step();
    EXPECT_FALSE(r.rolled_back);
    return (-s.probe_displacement("tip").z() - kBeamTip) / kBeamTip;
}
} // namespace

TEST(OctreeScene, CantileverWithRefinedRootMatchesTheBeam) {
    // refined to 5 cm near the clamp: hex cells away from it, polyhedra where 10 cm cells meet
    // 5 cm ones (their sides split into the finer faces, 001 Fig. 4)
    for (const std::string method : { "harmonic", "mvc" }) {
        sim::Simulation s(scene::parse_scene(cantilever(
            R"(, "regions": [{"lo": [0, 0, 0], "hi": [0.3, 0.3, 0.2], "cell_size": 0.05}])",
            method)));
        const sim::ModelStats st = s.model_stats();
        EXPECT_GT(st.hexes, 0);
        EXPECT_GT(st.polyhedra, 0);
        const double err = tip_error(s);
        std::printf(
            "octree cantilever (%s): %ld DOFs, %ld hexes, %ld polyhedra, tip error %+.2f %%\n",
            method.c_str(), long(st.dofs), long(st.hexes), long(st.polyhedra), 100 * err);
        EXPECT_LT(std::abs(err), 0.25) << method; // coarse Q1 hexes in bending: stiff
    }
}

TEST(OctreeScene, StressRefinementSplitsWithoutAPop) {
    // Dynamic: the beam swings down under its tip load (first bending period ~1.4 s); as the
    // cells near the clamp pass 400 Pa (static peak 864 Pa) they split 1-to-8. The children start from the parent's interpolated
    // displacement and velocity: the mechanical energy barely changes across the transfer.
    sim::Simulation s(scene::parse_scene(cantilever(R"(, "max_depth": 2, "refine_stress": 400)",
        "harmonic", R"({"type": "implicit_euler", "dt": 0.05, "corotated": true})")));
    const Index cells_before = s.cell_count();
    int refined = 0;
    double worst_jump = 0;
    for (int i = 0; i < 12; ++i) {
        const sim::StepReport r = s.step();
        ASSERT_FALSE(r.rolled_back) << i;
        if (r.cells_refined > 0) {
            EXPECT_TRUE(r.topology_changed);
            refined += r.cells_refined;
            const double scale = std::max(
                std::abs(r.refine_energy_before), s.energy().kinetic + s.energy().elastic);
            worst_jump = std::max(
                worst_jump, std::abs(r.refine_energy_after - r.refine_energy_before) / scale);
        }
    }
    EXPECT_GT(refined, 0);
    EXPECT_GT(s.cell_count(), cells_before + 7 * refined - 1);
    std::printf("octree refinement: %d cells split, %ld -> %ld cells, worst energy jump %.3e "
                "(relative)\n",
        refined, long(cells_before), long(s.cell_count()), worst_jump);
    EXPECT_LT(worst_jump, 0.05);
    EXPECT_GT(s.model_stats().polyhedra, 0);
}

TEST(OctreeScene, ImplicitOrganHasACoarseCoreAndAFineSkin) {
    const std::string text = R"({"name": "octree_blob",
      "geometry": {"type": "octree", "shape": "blob", "radii": [0.05, 0.05, 0.05],
                   "cell_size": 0.02, "surface_cell_size": 0.005},
      "method": "harmonic",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.45, "density": 1000,
                   "rayleigh_mass": 2},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "cholmod"},
      "fixed": [{"box": {"min": [-0.1, -0.1, -0.1], "max": [0.1, 0.1, -0.015]}}],
      "loads": {"gravity": [0, 0, -9.81]}})";
    sim::Simulation s(scene::parse_scene(text));
    const sim::ModelStats st = s.model_stats();
    EXPECT_GT(st.hexes, 0);
    EXPECT_GT(st.polyhedra, 0);
    const sim::MeshStats ms = s.mesh_stats();
    EXPECT_TRUE(ms.surface_closed);
    EXPECT_EQ(ms.components, 1);
    for (int i = 0; i < 3; ++i)
        EXPECT_FALSE(s.step().rolled_back);
    std::printf("octree blob: %ld DOFs, %ld hexes, %ld polyhedra\n", long(st.dofs), long(st.hexes),
        long(st.polyhedra));
}

TEST(OctreeScene, BadOctreeKeysNameTheField) {
    auto pointer_of = [](const std::string& extra) {
        try {
            scene::parse_scene(cantilever(extra));
        } catch (const SceneError& e) {
            return e.where();
        }
        return std::string("accepted");
    };
    EXPECT_EQ(pointer_of(R"(, "surface_cell_size": 0.05)"), "/geometry/surface_cell_size");
    EXPECT_EQ(pointer_of(R"(, "max_depth": 1, "regions": [{"lo": [0, 0, 0], "hi": [1, 1, 1],
        "cell_size": 0.01}])"),
        "/geometry/max_depth");
    EXPECT_EQ(pointer_of(R"(, "regions": [{"lo": [0, 0, 0], "hi": [0, 1, 1], "cell_size": 0.05}])"),
        "/geometry/regions/0/hi/0");
    EXPECT_EQ(pointer_of(R"(, "refine_stress": -1)"), "/geometry/refine_stress");
}
