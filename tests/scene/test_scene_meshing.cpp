// Scene keys of CGAL-meshed geometry (issue 18): surface_file's repair, components and wrap, and
// optimize / sliver_bound for surface_file and implicit. Defaults, every valid value, and each
// invalid value rejected with a JSON pointer at the key (or array element) that is wrong.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"

#include <gtest/gtest.h>
#include <string>
#include <vector>

using namespace polycut;
using namespace polycut::scene;

namespace {
const std::string kSurface = R"("type": "surface_file", "path": "organ.off", "cell_size": 0.008)";
const std::string kImplicit
    = R"("type": "implicit", "shape": "blob", "radii": [0.05, 0.05, 0.05], "cell_size": 0.01)";

std::string scene_with(const std::string& geometry, const std::string& extra) {
    return R"({"name": "organ", "geometry": {)" + geometry + (extra.empty() ? "" : ", ") + extra
        + R"(}, "material": {"youngs_modulus": 1e4}})";
}

Geometry surface(const std::string& extra = "") {
    return parse_scene(scene_with(kSurface, extra)).geometry;
}
Geometry implicit(const std::string& extra = "") {
    return parse_scene(scene_with(kImplicit, extra)).geometry;
}

/// JSON pointer of the SceneError parsing throws ("" if none).
std::string error_pointer(const std::string& geometry, const std::string& extra) {
    try {
        parse_scene(scene_with(geometry, extra));
    } catch (const SceneError& e) {
        return e.where();
    }
    return "";
}

const std::vector<std::string> kDefaultOptimize { "perturb", "exude" };
} // namespace

TEST(SceneMeshing, SurfaceFileDefaults) {
    const Geometry g = surface();
    EXPECT_EQ(g.kind, Geometry::Kind::SurfaceFile);
    EXPECT_EQ(g.repair, Repair::Auto);
    EXPECT_EQ(g.components, Components::Union);
    EXPECT_EQ(g.wrap_alpha, 0.0); // 0: cell_size, applied by the meshing
    EXPECT_EQ(g.wrap_offset, 0.0); // 0: cell_size / 30
    EXPECT_EQ(g.optimize, kDefaultOptimize);
    EXPECT_EQ(g.sliver_bound, 0.0);
    EXPECT_EQ(g.seed, 0u);
    EXPECT_EQ(g.scale, 1.0);
    EXPECT_DOUBLE_EQ(g.cell_size, 0.008);
}

TEST(SceneMeshing, SurfaceFileValidValues) {
    for (const char* mode : { "auto", "none", "pmp", "wrap" })
        EXPECT_STREQ(to_string(surface(std::string(R"("repair": ")") + mode + "\"").repair), mode);
    for (const char* mode : { "union", "largest", "refuse" })
        EXPECT_STREQ(
            to_string(surface(std::string(R"("components": ")") + mode + "\"").components), mode);

    Geometry g = surface(R"("repair": "wrap", "wrap": {"alpha": 0.004, "offset": 2e-4})");
    EXPECT_DOUBLE_EQ(g.wrap_alpha, 0.004);
    EXPECT_DOUBLE_EQ(g.wrap_offset, 2e-4);
    g = surface(R"("wrap": {"offset": 1e-4})"); // with the default repair "auto"
    EXPECT_EQ(g.wrap_alpha, 0.0);
    EXPECT_DOUBLE_EQ(g.wrap_offset, 1e-4);
    EXPECT_EQ(surface(R"("wrap": {})").wrap_alpha, 0.0);

    EXPECT_EQ(surface(R"("optimize": [])").optimize, std::vector<std::string>());
    EXPECT_EQ(surface(R"("optimize": ["lloyd", "odt", "perturb", "exude"])").optimize,
        (std::vector<std::string> { "lloyd", "odt", "perturb", "exude" }));
    EXPECT_EQ(surface(R"("optimize": ["exude"])").optimize, std::vector<std::string> { "exude" });
    EXPECT_DOUBLE_EQ(surface(R"("sliver_bound": 15)").sliver_bound, 15.0);
    EXPECT_DOUBLE_EQ(surface(R"("sliver_bound": 45)").sliver_bound, 45.0);
    EXPECT_DOUBLE_EQ(surface(R"("scale": 0.001, "seed": 7)").scale, 0.001);
}

TEST(SceneMeshing, SurfaceFileInvalidValuesPointAtTheKey) {
    const std::vector<std::pair<std::string, std::string>> cases {
        { R"("repair": "fix")", "/geometry/repair" },
        { R"("repair": "PMP")", "/geometry/repair" },
        { R"("repair": true)", "/geometry/repair" },
        { R"("components": "all")", "/geometry/components" },
        { R"("components": 2)", "/geometry/components" },
        { R"("repair": "pmp", "wrap": {"alpha": 0.004})", "/geometry/wrap" },
        { R"("repair": "none", "wrap": {})", "/geometry/wrap" },
        { R"("wrap": 0.004)", "/geometry/wrap" },
        { R"("wrap": {"alpha": 0})", "/geometry/wrap/alpha" },
        { R"("wrap": {"alpha": -0.004})", "/geometry/wrap/alpha" },
        { R"("wrap": {"alpha": "big"})", "/geometry/wrap/alpha" },
        { R"("wrap": {"alpha": 2000})", "/geometry/wrap/alpha" },
        { R"("wrap": {"offset": 0})", "/geometry/wrap/offset" },
        { R"("wrap": {"offset": null})", "/geometry/wrap/offset" },
        { R"("wrap": {"radius": 0.004})", "/geometry/wrap/radius" },
        { R"("optimize": "perturb")", "/geometry/optimize" },
        { R"("optimize": {"perturb": true})", "/geometry/optimize" },
        { R"("optimize": ["smooth"])", "/geometry/optimize/0" },
        { R"("optimize": ["perturb", 3])", "/geometry/optimize/1" },
        { R"("optimize": ["exude", "perturb", "exude"])", "/geometry/optimize/2" },
        { R"("sliver_bound": -1)", "/geometry/sliver_bound" },
        { R"("sliver_bound": 46)", "/geometry/sliver_bound" },
        { R"("sliver_bound": "15")", "/geometry/sliver_bound" },
        { R"("repairs": "auto")", "/geometry/repairs" },
    };
    for (const auto& [extra, pointer] : cases)
        EXPECT_EQ(error_pointer(kSurface, extra), pointer) << extra;
}

TEST(SceneMeshing, MessagesListTheAllowedValues) {
    try {
        surface(R"("repair": "fix")");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        for (const char* mode : { "\"auto\"", "\"none\"", "\"pmp\"", "\"wrap\"", "\"fix\"" })
            EXPECT_NE(e.problem().find(mode), std::string::npos) << e.what();
    }
    try {
        surface(R"("optimize": ["smooth"])");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        for (const char* name : { "lloyd", "odt", "perturb", "exude" })
            EXPECT_NE(e.problem().find(name), std::string::npos) << e.what();
    }
}

TEST(SceneMeshing, ImplicitOptimizeAndSliverBound) {
    Geometry g = implicit();
    EXPECT_EQ(g.kind, Geometry::Kind::Implicit);
    EXPECT_EQ(g.optimize, kDefaultOptimize);
    EXPECT_EQ(g.sliver_bound, 0.0);
    g = implicit(R"("optimize": ["odt", "perturb"], "sliver_bound": 12.5)");
    EXPECT_EQ(g.optimize, (std::vector<std::string> { "odt", "perturb" }));
    EXPECT_DOUBLE_EQ(g.sliver_bound, 12.5);
    EXPECT_EQ(error_pointer(kImplicit, R"("optimize": ["lloyd", "cvt"])"), "/geometry/optimize/1");
    EXPECT_EQ(error_pointer(kImplicit, R"("sliver_bound": 90)"), "/geometry/sliver_bound");
    // Surface repair keys belong to surface_file only.
    EXPECT_EQ(error_pointer(kImplicit, R"("repair": "auto")"), "/geometry/repair");
    EXPECT_EQ(error_pointer(kImplicit, R"("components": "union")"), "/geometry/components");
    EXPECT_EQ(error_pointer(kImplicit, R"("wrap": {})"), "/geometry/wrap");
}

TEST(SceneMeshing, MeshFileTakesNoMeshingKeys) {
    const std::string mesh_file = R"("type": "mesh_file", "path": "organ.msh")";
    EXPECT_EQ(error_pointer(mesh_file, ""), "");
    for (const char* key : { "repair", "components", "optimize", "sliver_bound", "wrap" })
        EXPECT_EQ(error_pointer(mesh_file, std::string("\"") + key + "\": 1"),
            std::string("/geometry/") + key)
            << key;
}

TEST(SceneMeshing, NodeOrder) {
    // issue 18: meshed tets are renumbered by reverse Cuthill-McKee unless the scene keeps
    // Mesh_3's order
    EXPECT_EQ(implicit().node_order, NodeOrder::Rcm);
    EXPECT_EQ(surface().node_order, NodeOrder::Rcm);
    EXPECT_EQ(implicit(R"("node_order": "mesher")").node_order, NodeOrder::Mesher);
    EXPECT_EQ(surface(R"("node_order": "mesher")").node_order, NodeOrder::Mesher);
    EXPECT_EQ(error_pointer(kImplicit, R"("node_order": "metis")"), "/geometry/node_order");
}
