// Octree geometry through the facade (issue 15 item 3; 001 sec. 7-8): a box cantilever on an
// adaptive octree with polyhedral transition cells against the beam formula, an implicit organ
// embedded in an octree (coarse core, fine skin) with its detailed surface, stress-based 1-to-8
// refinement while it runs with the state carried over without a pop, and the scene's errors.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>
#include <map>

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
    // cells near the clamp pass 400 Pa (static peak 864 Pa) they split 1-to-8. The children start
    // from the parent's interpolated displacement and velocity: the mechanical energy barely
    // changes across the transfer.
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

namespace {
/// The blob organ (radii 5 cm) on an octree, hanging under gravity from its bottom 1 cm, linear
/// static: the displacement at rest-space points near the top.
std::string organ(double cell_size, double surface_cell_size) {
    return R"({"name": "octree_organ",
      "geometry": {"type": "octree", "shape": "blob", "radii": [0.05, 0.05, 0.05],
                   "cell_size": )"
        + std::to_string(cell_size) + R"(, "surface_cell_size": )"
        + std::to_string(surface_cell_size) + R"(},
      "method": "harmonic",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3, "density": 1000},
      "integrator": {"type": "static", "corotated": false, "tolerance": 1e-8},
      "solver": {"type": "cholmod"},
      "fixed": [{"box": {"min": [-0.1, -0.1, -0.1], "max": [0.1, 0.1, -0.015]}}],
      "loads": {"gravity": [0, 0, -9.81]}})";
}

struct Solution {
    long dofs = 0;
    std::vector<Vec3> u;
};

Solution solve_at(const std::string& text, const std::vector<Vec3>& points) {
    sim::Simulation s(scene::parse_scene(text));
    EXPECT_FALSE(s.step().rolled_back);
    Solution r;
    r.dofs = long(s.model_stats().dofs);
    std::vector<std::uint8_t> inside;
    s.sample_displacements(points, r.u, inside);
    for (std::uint8_t in : inside)
        EXPECT_TRUE(in);
    return r;
}

double relative_error(const Solution& run, const Solution& reference) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < run.u.size(); ++i) {
        num += (run.u[i] - reference.u[i]).squaredNorm();
        den += reference.u[i].squaredNorm();
    }
    return std::sqrt(num / den);
}
} // namespace

TEST(OctreeScene, OrganOctreeNeedsFewerDofsThanAUniformGridForTheSameError) {
    // 001 sec. 7 / Fig. 7: DOFs at the surface, a coarse core. The octree with 5 mm cells at
    // the surface and 2 cm inside against the uniform 5 mm grid (the same skin of kept boundary
    // cells), both against a uniform 2.5 mm reference, at points inside the organ.
    std::vector<Vec3> points;
    for (double x : { -0.03, -0.015, 0.0, 0.015, 0.03 })
        for (double y : { -0.01, 0.0, 0.01 })
            points.push_back(Vec3(x, y, 0.01));
    const Solution reference = solve_at(organ(0.0025, 0.0025), points);
    const Solution uniform = solve_at(organ(0.005, 0.005), points);
    const Solution octree = solve_at(organ(0.02, 0.005), points);
    const Solution fine_skin = solve_at(organ(0.02, 0.0025), points);
    const Solution mid_core = solve_at(organ(0.01, 0.0025), points);
    const double e_uniform = relative_error(uniform, reference);
    const double e_octree = relative_error(octree, reference);
    const double e_fine_skin = relative_error(fine_skin, reference);
    const double e_mid_core = relative_error(mid_core, reference);
    std::printf("organ: reference (uniform 2.5 mm) %ld DOFs; uniform 5 mm %ld DOFs, error %.2f %%; "
                "octree 5 mm / 2 cm %ld DOFs, error %.2f %%; octree 2.5 mm / 2 cm %ld DOFs, error "
                "%.2f %%; octree 2.5 mm / 1 cm %ld DOFs, error %.2f %%\n",
        reference.dofs, uniform.dofs, 100 * e_uniform, octree.dofs, 100 * e_octree, fine_skin.dofs,
        100 * e_fine_skin, mid_core.dofs, 100 * e_mid_core);
    EXPECT_LT(octree.dofs, uniform.dofs);
    EXPECT_LT(e_octree, 1.5 * e_uniform + 0.01);
    // the interior coarsened from 2.5 mm to 2 cm costs under 2 % against the 2.5 mm grid
    EXPECT_LT(fine_skin.dofs, 0.85 * double(reference.dofs));
    EXPECT_LT(e_fine_skin, 0.02);
}

TEST(OctreeScene, CantileverAdaptiveAgainstUniform) {
    // Tip deflection against the beam formula: uniform octrees (all Q1 hexes) of 10, 5 and
    // 2.5 cm, and octrees refined where the bending stress is high (near the clamp) or by the
    // stress itself (static solve, split, solve again).
    struct Case {
        const char* name;
        std::string keys;
        int steps = 1;
    };
    const std::vector<Case> cases {
        { "uniform 10 cm", "" },
        { "uniform 5 cm",
            R"(, "regions": [{"lo": [0, 0, 0], "hi": [1.2, 0.3, 0.2], "cell_size": 0.05}])" },
        { "uniform 2.5 cm",
            R"(, "regions": [{"lo": [0, 0, 0], "hi": [1.2, 0.3, 0.2], "cell_size": 0.025}])" },
        { "5 cm for x < 0.6 m",
            R"(, "regions": [{"lo": [0, 0, 0], "hi": [0.6, 0.3, 0.2], "cell_size": 0.05}])" },
        { "2.5 cm for x < 0.3 m, 5 cm to 0.7 m",
            R"(, "regions": [{"lo": [0, 0, 0], "hi": [0.3, 0.3, 0.2], "cell_size": 0.025}, {"lo": [0, 0, 0], "hi": [0.7, 0.3, 0.2], "cell_size": 0.05}])" },
        { "stress > 400 Pa split, 2 levels", R"(, "max_depth": 2, "refine_stress": 400)", 3 },
    };
    for (const Case& c : cases) {
        sim::Simulation s(scene::parse_scene(cantilever(c.keys)));
        double err = 0;
        for (int i = 0; i < c.steps; ++i)
            err = tip_error(s);
        const sim::ModelStats st = s.model_stats();
        std::printf(
            "cantilever octree %s: %ld DOFs (%ld hexes, %ld polyhedra), tip error %+.2f %%\n",
            c.name, long(st.dofs), long(st.hexes), long(st.polyhedra), 100 * err);
        EXPECT_LT(std::abs(err), 0.25) << c.name;
    }
}

TEST(OctreeScene, ShippedOrganOctreeIsCutLive) {
    // assets/scenes/organ_octree.json: the octree organ with its 79,872-triangle embedded
    // surface settles on the table, and a blade is drawn 7 cm across its top, 1.75 cm deep,
    // a few sweep triangles per tick, as polycut-scalpel sends organ_octree_incision.json.
    sim::Simulation s(
        scene::load_scene(std::string(POLYCUT_SOURCE_DIR) + "/assets/scenes/organ_octree.json"));
    const sim::ModelStats st = s.model_stats();
    EXPECT_GT(st.hexes, 0);
    EXPECT_GT(st.polyhedra, 0);
    const sim::Surface skin = s.surface();
    EXPECT_EQ(skin.triangles.size(), 3 * std::size_t(79872)); // the embedded surface
    std::vector<double> step_ms;
    for (int i = 0; i < 30; ++i) {
        const sim::StepReport r = s.step();
        ASSERT_FALSE(r.rolled_back) << i;
        step_ms.push_back(r.step_ms);
    }
    const Vec3 blade(0, 0, -0.045);
    const int samples = 24;
    auto at = [&](int k) { return Vec3(-0.035 + 0.07 * k / samples, 0.0025, 0.05); };
    auto open_edges = [](const sim::Surface& surface) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
        for (std::size_t t = 0; t < surface.triangles.size(); t += 3)
            for (int k = 0; k < 3; ++k)
                ++edges[{ surface.triangles[t + std::size_t(k)],
                    surface.triangles[t + std::size_t((k + 1) % 3)] }];
        int open_count = 0;
        for (const auto& [edge, uses] : edges) {
            const auto back = edges.find({ edge.second, edge.first });
            open_count += uses != 1 || back == edges.end() || back->second != 1;
        }
        return open_count;
    };
    int applied = 0, undone = 0, open_sweeps = 0;
    std::vector<double> embed_ms, split_ms, corefine_ms, patch, reembedded, cut_ms;
    for (int k = 0; k < samples; ++k) {
        const Vec3 a = at(k), b = at(k + 1);
        const sim::CutSummary c = s.cut({ { a, a + blade, b }, { b, a + blade, b + blade } });
        applied += c.status == sim::CutSummary::Status::Applied;
        if (c.topology_changed) {
            const sim::EmbeddedStats es = s.embedded_stats();
            ASSERT_TRUE(es.split) << k;
            embed_ms.push_back(es.embed_ms);
            split_ms.push_back(es.split_ms);
            corefine_ms.push_back(es.corefine_ms);
            patch.push_back(double(es.patch_triangles));
            reembedded.push_back(double(es.reembedded));
            cut_ms.push_back(c.cut_ms);
        }
        const sim::StepReport r = s.step();
        // a step that fails right after a cut undoes that cut and the tissue steps on (the
        // server's contract); any other failure is one
        ASSERT_TRUE(!r.rolled_back || r.cut_undone)
            << k << ": " << (r.warnings.empty() ? "" : r.warnings.front());
        undone += r.cut_undone;
        step_ms.push_back(r.step_ms);
        open_sweeps += open_edges(s.surface()) > 0;
    }
    s.end_stroke();
    for (int i = 0; i < 20; ++i)
        ASSERT_FALSE(s.step().rolled_back) << i;
    EXPECT_GT(applied - undone, samples / 2);
    EXPECT_LE(undone, 2);
    const sim::MeshStats ms = s.mesh_stats();
    EXPECT_GT(ms.cut_area, 0.5 * 0.06 * 0.015); // most of the 7 x 1.75 cm swept through the organ
    const sim::Surface cut = s.surface();
    std::size_t lips = 0;
    for (std::uint8_t tag : cut.tags)
        lips += tag == 2;
    EXPECT_GT(lips, 0u);
    // The detailed surface is split along the cut (decision 0033): closed and oriented, its
    // lips carry tag 2.
    EXPECT_EQ(open_edges(cut), 0);
    EXPECT_GT(cut.triangles.size(), 3 * std::size_t(79872)); // the skin was split
    // Between sweeps the published surface may be open for a tick where a lip pair meets the
    // crack front at a skin vertex (decision 0033, "Not done"); measured 2 of 24.
    EXPECT_LE(open_sweeps, 3);
    auto median = [](std::vector<double> v) {
        if (v.empty())
            return 0.0;
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    auto largest = [](const std::vector<double>& v) {
        return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
    };
    std::printf(
        "organ_octree split per cut (%zu cuts): embed %.1f ms median / %.1f max (split %.1f "
        "/ %.1f, CGAL corefine %.1f / %.1f), patch %.0f / %.0f of %zu skin triangles, "
        "%.0f / %.0f vertices re-embedded; cut_ms %.1f / %.1f; %d of %d sweeps left the surface "
        "open until the next\n",
        embed_ms.size(), median(embed_ms), largest(embed_ms), median(split_ms), largest(split_ms),
        median(corefine_ms), largest(corefine_ms), median(patch), largest(patch),
        std::size_t(79872), median(reembedded), largest(reembedded), median(cut_ms),
        largest(cut_ms), open_sweeps, samples);
    std::sort(step_ms.begin(), step_ms.end());
    std::printf("organ_octree: %ld DOFs (%ld hexes, %ld polyhedra), %d of %d sweeps applied, %d "
                "undone by the next step, cut area %.2f cm^2, %zu lip triangles, step median %.1f "
                "ms, max %.1f ms\n",
        long(st.dofs), long(st.hexes), long(st.polyhedra), applied, samples, undone,
        ms.cut_area * 1e4, lips, step_ms[step_ms.size() / 2], step_ms.back());
}

TEST(OctreeScene, SurfaceFileObjectIsCoveredByTheCells) {
    // The object as a surface file (liver_blob.off, its exact signed distance through an AABB
    // tree). keep "cover": the kept cells cover it, so their volume exceeds the enclosed
    // 134 cm^3, by less than a shell of one surface cell's diagonal; keep "centre" (default):
    // the cells whose centre is inside, within a few percent of it.
    const std::string text = R"({"name": "octree_file",
      "geometry": {"type": "octree", "path": ")"
        + std::string(POLYCUT_SOURCE_DIR) + R"(/assets/meshes/liver_blob.off",
                   "cell_size": 0.02, "surface_cell_size": 0.005, "keep": "cover"},
      "method": "mvc",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.45, "density": 1000},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "cholmod"},
      "fixed": [{"box": {"min": [-0.1, -0.1, -0.1], "max": [0.1, 0.1, -0.015]}}]})";
    {
        std::string centre = text;
        centre.replace(centre.find(", \"keep\": \"cover\""), 17, "");
        sim::Simulation c(scene::parse_scene(centre));
        const double v = c.mesh_stats().rest_volume;
        std::printf("octree of liver_blob.off, keep centre: %.1f cm^3\n", v * 1e6);
        EXPECT_NEAR(v, 134e-6, 0.1 * 134e-6);
    }
    sim::Simulation s(scene::parse_scene(text));
    const sim::MeshStats ms = s.mesh_stats();
    EXPECT_TRUE(ms.surface_closed);
    EXPECT_EQ(ms.components, 1);
    EXPECT_GT(s.model_stats().polyhedra, 0);
    const double enclosed = 134e-6, area = 110e-4; // [m^3], ~[m^2] of the blob
    EXPECT_GT(ms.rest_volume, enclosed);
    EXPECT_LT(ms.rest_volume, enclosed + area * 0.005 * std::sqrt(3.0));
    EXPECT_FALSE(s.step().rolled_back);
    std::printf("octree of liver_blob.off: %ld cells, %.1f cm^3 (enclosed 134)\n",
        long(s.cell_count()), ms.rest_volume * 1e6);
}
