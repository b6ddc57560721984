// Scene JSON parser (docs/scenes.md). Every field is validated where it is read; errors carry a
// JSON pointer and say what is allowed; unknown keys are errors.
#include "polycut/scene/scene.hpp"

#include "json_reader.hpp"
#include "scene_contact.hpp"
#include "scene_octree.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace polycut::scene {
namespace {
using namespace detail; // json, ObjectReader, the name tables
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxLength = 1e3; // [m] anything larger is a unit mistake

constexpr std::size_t kMaxHullPoints = 1000; // one cell: beyond this a mesh is wanted

/// One convex cell: explicit `points` (and `scale`) or a named `shape` (`size`, `center`).
/// Whether the points are all corners of their hull is checked when the mesh is built.
void parse_convex_hull(ObjectReader& r, Geometry& g) {
    g.kind = Geometry::Kind::ConvexHull;
    const bool has_points = r.has("points");
    const bool has_shape = r.has("shape");
    if (has_points == has_shape)
        r.fail(has_points ? "shape" : "points",
            has_points ? "give either \"points\" or \"shape\", not both"
                       : "is required (an array of >= 4 [x, y, z] corners [m]), or give a "
                         "\"shape\"");
    if (has_shape) {
        g.shape = r.choice_required("shape", kHullShape);
        g.edge_length = r.number_required("size", 0, kMaxLength, true, "m");
        g.center = r.vec3("center", g.center, false, "m");
    } else {
        const json& pts = r.get("points");
        if (!pts.is_array() || pts.size() < 4 || pts.size() > kMaxHullPoints)
            r.fail("points",
                "must be an array of 4 to " + std::to_string(kMaxHullPoints)
                    + " points [x, y, z] [m] (the corners of one convex cell)");
        for (std::size_t i = 0; i < pts.size(); ++i)
            g.points.push_back(
                ObjectReader::parse_vec3(pts[i], r.child("points") + "/" + std::to_string(i), "m"));
        g.scale = r.number("scale", 1.0, 0, kMaxLength, true);
        for (std::size_t i = 0; i < g.points.size(); ++i)
            if (!(g.points[i].cwiseAbs().maxCoeff() * g.scale <= kMaxLength))
                throw SceneError(r.child("points") + "/" + std::to_string(i),
                    "coordinates times scale must be within [-1000, 1000] [m]");
    }
}

/// Mesh_3 optimisers: an array of distinct names.
std::vector<std::string> parse_optimize(ObjectReader& r, std::vector<std::string> fallback) {
    if (!r.has("optimize"))
        return fallback;
    const json& a = r.get("optimize");
    const auto allowed = { "lloyd", "odt", "perturb", "exude" };
    if (!a.is_array())
        r.fail("optimize",
            "must be an array of \"lloyd\", \"odt\", \"perturb\", \"exude\" (run in that "
            "order)");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string at = r.child("optimize") + "/" + std::to_string(i);
        if (!a[i].is_string() || std::none_of(allowed.begin(), allowed.end(), [&](const char* n) {
                return a[i].get<std::string>() == n;
            }))
            throw SceneError(at, "must be one of \"lloyd\", \"odt\", \"perturb\", \"exude\"");
        if (std::find(out.begin(), out.end(), a[i].get<std::string>()) != out.end())
            throw SceneError(at, "repeats \"" + a[i].get<std::string>() + "\"");
        out.push_back(a[i].get<std::string>());
    }
    return out;
}

/// surface_file: repair, components and the wrap's size.
void parse_surface_repair(ObjectReader& r, Geometry& g) {
    g.repair = r.choice("repair", g.repair, kRepair);
    g.components = r.choice("components", g.components, kComponents);
    if (r.has("wrap")) {
        if (g.repair != Repair::Auto && g.repair != Repair::Wrap)
            r.fail("wrap", "is only used with \"repair\": \"auto\" or \"wrap\"");
        ObjectReader w(r.get("wrap"), r.child("wrap"));
        g.wrap_alpha = w.number("alpha", 0, 0, kMaxLength, true, "m");
        g.wrap_offset = w.number("offset", 0, 0, kMaxLength, true, "m");
        w.finish();
    }
}

/// The implicit shape fields (geometry "implicit" and "octree", and hex_slice's "surface"
/// object).
void parse_implicit_shape(ObjectReader& r, Geometry& g) {
    g.shape = r.choice_required("shape", kImplicitShape);
    g.center = r.vec3("center", g.center, false, "m");
    if (g.shape == Shape::Sphere || g.shape == Shape::Capsule || g.shape == Shape::HollowSphere) {
        const double radius = r.number_required("radius", 0, kMaxLength, true, "m");
        g.radii = Vec3::Constant(radius);
        if (g.shape == Shape::HollowSphere) {
            g.inner_radius = r.number_required("inner_radius", 0, kMaxLength, true, "m");
            if (!(g.inner_radius < radius))
                r.fail("inner_radius", "must be smaller than \"radius\"");
        }
    } else {
        g.radii = r.vec3("radii", g.radii, g.shape == Shape::Ellipsoid, "m");
        for (int i = 0; i < 3; ++i)
            if (!(g.radii[i] > 0))
                throw SceneError(r.child("radii") + "/" + std::to_string(i), "must be > 0 [m]");
    }
    if (g.shape == Shape::Capsule)
        g.length = r.number_required("length", 0, kMaxLength, false, "m");
}

/// hex_slice (003 sec. 10): a grid of cubes of `cell_size` intersected with a closed surface, a
/// file (string) or an implicit shape (object).
void parse_hex_slice(ObjectReader& r, Geometry& g) {
    g.kind = Geometry::Kind::HexSlice;
    const json& surface = r.get("surface");
    if (surface.is_string()) {
        g.path = surface.get<std::string>();
        if (g.path.empty())
            r.fail("surface", "must name a surface file (relative to the scene file)");
        g.scale = r.number("scale", 1.0, 0, kMaxLength, true);
        parse_surface_repair(r, g);
    } else if (surface.is_object()) {
        ObjectReader sr(surface, r.child("surface"));
        parse_implicit_shape(sr, g);
        g.triangle_size = sr.number("triangle_size", 0, 0, kMaxLength, false, "m");
        g.seed = unsigned(sr.integer("seed", 0, 0, std::numeric_limits<int>::max()));
        sr.finish();
    } else {
        r.fail("surface",
            "must be a surface file path or an implicit shape {\"shape\": \"sphere\", ...}");
    }
    g.cell_size = r.number_required("cell_size", 0, kMaxLength, true, "m");
    g.merge_fraction = r.number("merge_fraction", g.merge_fraction, 0, 0.99, false);
}

Geometry parse_geometry(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Geometry g;
    const Geometry::Kind type = r.choice_required("type", kGeometryKind);
    if (type == Geometry::Kind::Box || type == Geometry::Kind::RandomPlanes) {
        g.kind = type;
        if (type == Geometry::Kind::Box && r.has("corners")) {
            // A hexahedron given by its corners instead of origin and size.
            if (r.has("origin") || r.has("size"))
                r.fail("corners", "replaces \"origin\" and \"size\"; give one or the other");
            const json& c = r.get("corners");
            if (!c.is_array() || c.size() != 8)
                r.fail("corners", "must be an array of 8 points [x, y, z] [m] in VTK hex order");
            for (std::size_t i = 0; i < 8; ++i) {
                const std::string at = r.child("corners") + "/" + std::to_string(i);
                g.corners.push_back(ObjectReader::parse_vec3(c[i], at, "m"));
                if (!(g.corners.back().cwiseAbs().maxCoeff() <= kMaxLength))
                    throw SceneError(at, "coordinates must be within [-1000, 1000] [m]");
            }
        } else {
            g.origin = r.vec3("origin", g.origin, false, "m");
            g.size = r.vec3("size", g.size, true, "m");
        }
        for (int i = 0; i < 3; ++i)
            if (!(g.size[i] > 0) || g.size[i] > kMaxLength)
                throw SceneError(
                    r.child("size") + "/" + std::to_string(i), "must be in (0, 1000] [m]");
        if (r.has("cells")) {
            const json& c = r.get("cells");
            if (!c.is_array() || c.size() != 3)
                r.fail("cells", "must be an array of 3 positive integers");
            for (int i = 0; i < 3; ++i) {
                const json& e = c[std::size_t(i)];
                if (!e.is_number_integer() || e.get<long>() < 1 || e.get<long>() > 1000)
                    throw SceneError(r.child("cells") + "/" + std::to_string(i),
                        "must be an integer in [1, 1000]");
                g.cells[i] = e.get<int>();
            }
        }
        g.elements = r.choice("elements", g.elements, kElements);
        g.tet_split = r.choice("tet_split", g.tet_split, kTetSplit);
        if (g.kind == Geometry::Kind::RandomPlanes)
            g.planes_per_cell = int(r.integer("planes_per_cell", 3, 1, 64));
        g.seed = unsigned(r.integer("seed", 1, 0, std::numeric_limits<int>::max()));
    } else if (type == Geometry::Kind::Implicit) {
        g.kind = Geometry::Kind::Implicit;
        parse_implicit_shape(r, g);
        g.cell_size = r.number_required("cell_size", 0, kMaxLength, true, "m");
        g.seed = unsigned(r.integer("seed", 0, 0, std::numeric_limits<int>::max()));
        g.optimize = parse_optimize(r, g.optimize);
        g.node_order = r.choice("node_order", g.node_order, kNodeOrder);
        g.sliver_bound = r.number("sliver_bound", g.sliver_bound, 0, 45, false, "deg");
    } else if (type == Geometry::Kind::Octree) {
        g.kind = Geometry::Kind::Octree;
        if (r.has("shape") && r.has("path"))
            r.fail(
                "path", "give either an implicit \"shape\" or a surface file \"path\", not both");
        if (r.has("shape")) {
            g.octree.object = OctreeObject::Implicit;
            parse_implicit_shape(r, g);
        } else if (r.has("path")) {
            g.octree.object = OctreeObject::SurfaceFile;
            g.path = r.string("path", "");
            g.scale = r.number("scale", 1.0, 0, kMaxLength, true);
        } else {
            g.origin = r.vec3("origin", g.origin, false, "m");
            g.size = r.vec3("size", g.size, true, "m");
            for (int i = 0; i < 3; ++i)
                if (!(g.size[i] > 0) || g.size[i] > kMaxLength)
                    throw SceneError(
                        r.child("size") + "/" + std::to_string(i), "must be in (0, 1000] [m]");
        }
        g.cell_size = r.number_required("cell_size", 0, kMaxLength, true, "m");
        detail::parse_octree(r, g);
    } else if (type == Geometry::Kind::ConvexHull) {
        parse_convex_hull(r, g);
    } else if (type == Geometry::Kind::HexSlice) {
        parse_hex_slice(r, g);
    } else {
        g.kind = type; // SurfaceFile or MeshFile
        g.path = r.string("path", "");
        if (g.path.empty())
            r.fail("path", "is required (a file path relative to the scene file)");
        g.scale = r.number("scale", 1.0, 0, kMaxLength, true);
        if (g.kind == Geometry::Kind::SurfaceFile) {
            g.cell_size = r.number_required("cell_size", 0, kMaxLength, true, "m");
            g.seed = unsigned(r.integer("seed", 0, 0, std::numeric_limits<int>::max()));
            g.optimize = parse_optimize(r, g.optimize);
            g.node_order = r.choice("node_order", g.node_order, kNodeOrder);
            g.sliver_bound = r.number("sliver_bound", g.sliver_bound, 0, 45, false, "deg");
            parse_surface_repair(r, g);
        }
    }
    r.finish();
    return g;
}

Material parse_material(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Material m;
    m.youngs_modulus = r.number_required("youngs_modulus", 0, 1e12, true, "Pa");
    m.poisson_ratio = r.number("poisson_ratio", m.poisson_ratio, -0.999, 0.4999);
    m.density = r.number("density", m.density, 0, 1e5, true, "kg/m^3");
    m.rayleigh_mass = r.number("rayleigh_mass", m.rayleigh_mass, 0, 1e6, false, "1/s");
    m.rayleigh_stiffness = r.number("rayleigh_stiffness", m.rayleigh_stiffness, 0, 1e3, false, "s");
    r.finish();
    return m;
}

Basis parse_basis(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Basis b;
    b.rule = r.choice("rule", b.rule, kPolyRule);
    b.gauss_degree = int(r.integer("gauss_degree", b.gauss_degree, 1, 8));
    b.harmonic_xi = r.number("harmonic_xi", b.harmonic_xi, 0, 10, true);
    b.volumetric = r.choice("volumetric", b.volumetric, kVolumetric);
    b.degree = int(r.integer("degree", b.degree, 1, 2));
    r.finish();
    return b;
}

Dg parse_dg(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Dg d;
    d.flux = r.choice("flux", d.flux, kFlux);
    d.penalty = r.number("penalty", d.penalty, 0, 1e6, true);
    d.dirichlet_penalty = r.number("dirichlet_penalty", d.dirichlet_penalty, 0, 1e8, true);
    d.lambda_penalty = r.choice("lambda_penalty", d.lambda_penalty, kLambdaPenalty);
    d.refine_stress = r.number("refine_stress", d.refine_stress, 0, 1e12, false, "Pa");
    d.refine_levels = int(r.integer("refine_levels", d.refine_levels, 1, 6));
    r.finish();
    return d;
}

Integrator parse_integrator(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Integrator it;
    it.type = r.choice("type", it.type, kIntegrator);
    it.dt = r.number("dt", it.dt, 0, 10, true, "s");
    it.corotated = r.boolean("corotated", it.corotated);
    it.static_mode = r.choice("static_mode", it.static_mode, kStaticMode);
    it.tolerance = r.number("tolerance", it.tolerance, 0, 1, true);
    it.max_iterations = int(r.integer("max_iterations", it.max_iterations, 1, 100000));
    it.threads = int(r.integer("threads", it.threads, 1, 256));
    it.stiffness_every = int(r.integer("stiffness_every", it.stiffness_every, 1, 1000));
    it.energy_guard = r.boolean("energy_guard", it.energy_guard);
    r.finish();
    return it;
}

Solver parse_solver(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Solver s;
    s.type = r.choice("type", s.type, kSolverType);
    s.preconditioner = r.choice("preconditioner", s.preconditioner, kPreconditioner);
    s.tolerance = r.number("tolerance", s.tolerance, 0, 1, true);
    s.load_tolerance = r.number("load_tolerance", s.load_tolerance, 0, 1, false);
    s.max_iterations = int(r.integer("max_iterations", s.max_iterations, 1, 1000000));
    s.iteration_budget = int(r.integer("iteration_budget", s.iteration_budget, 0, 1000000));
    s.refactor_every = int(r.integer("refactor_every", s.refactor_every, 0, 1000000));
    s.refactor_iterations
        = int(r.integer("refactor_iterations", s.refactor_iterations, 0, 1000000));
    s.warm_start = r.choice("warm_start", s.warm_start, kWarmStart);
    s.start_vectors = int(r.integer("start_vectors", s.start_vectors, 1, 32));
    if (r.has("amg")) {
        ObjectReader a(r.get("amg"), r.child("amg"));
        s.amg_strong_threshold = a.number("strong_threshold", s.amg_strong_threshold, 0, 1, true);
        s.amg_aggressive_levels
            = int(a.integer("aggressive_levels", s.amg_aggressive_levels, 0, 10));
        s.amg_interpolation_max_elements = int(
            a.integer("interpolation_max_elements", s.amg_interpolation_max_elements, 0, 100));
        s.amg_max_coarse_size = int(a.integer("max_coarse_size", s.amg_max_coarse_size, 1, 4000));
        s.amg_rigid_body_modes = a.boolean("rigid_body_modes", s.amg_rigid_body_modes);
        s.amg_node_blocks = a.boolean("node_blocks", s.amg_node_blocks);
        s.amg_background_solves
            = int(a.integer("background_solves", s.amg_background_solves, 0, 1000));
        s.amg_background_serial = a.boolean("background_serial", s.amg_background_serial);
        s.amg_refresh_delay = int(a.integer("refresh_delay", s.amg_refresh_delay, 0, 1000));
        a.finish();
    }
    r.finish();
    return s;
}

Selector parse_selector(
    ObjectReader& parent, const std::string& ptr_key_box, const std::string& ptr_key_plane) {
    Selector s;
    const bool box = parent.has(ptr_key_box);
    const bool plane = parent.has(ptr_key_plane);
    if (box == plane)
        parent.fail(
            "", "needs exactly one of \"" + ptr_key_box + "\" or \"" + ptr_key_plane + "\"");
    if (box) {
        ObjectReader r(parent.get(ptr_key_box), parent.child(ptr_key_box));
        s.kind = Selector::Kind::Box;
        s.min = r.vec3("min", s.min, true, "m");
        s.max = r.vec3("max", s.max, true, "m");
        s.tolerance = r.number("padding", 1e-9, 0, kMaxLength, false, "m");
        for (int i = 0; i < 3; ++i)
            if (s.min[i] > s.max[i])
                r.fail("max", "must be >= min in every component");
        r.finish();
    } else {
        ObjectReader r(parent.get(ptr_key_plane), parent.child(ptr_key_plane));
        s.kind = Selector::Kind::Plane;
        s.point = r.vec3("point", s.point, true, "m");
        s.normal = r.vec3("normal", s.normal, true);
        if (!(s.normal.norm() > 0))
            r.fail("normal", "must be a non-zero vector");
        s.normal.normalize();
        s.tolerance = r.number("tolerance", 1e-9, 0, kMaxLength, false, "m");
        r.finish();
    }
    return s;
}

std::array<bool, 3> parse_components(ObjectReader& r) {
    const std::string c = r.string("components", "xyz");
    std::array<bool, 3> out { false, false, false };
    if (c.empty())
        r.fail("components", "must name at least one of x, y, z");
    for (char ch : c) {
        if (ch < 'x' || ch > 'z')
            r.fail("components", "must be letters from \"xyz\", got \"" + c + "\"");
        out[std::size_t(ch - 'x')] = true;
    }
    return out;
}

template <class F> void for_each_item(ObjectReader& r, const std::string& key, F&& f) {
    if (!r.has(key))
        return;
    const json& arr = r.get(key);
    if (!arr.is_array())
        r.fail(key, "must be an array");
    for (std::size_t i = 0; i < arr.size(); ++i)
        f(arr[i], r.child(key) + "/" + std::to_string(i));
}

Cutting parse_cutting(const json& j, const std::string& ptr, CutMethod default_method) {
    ObjectReader r(j, ptr);
    Cutting c;
    c.method = r.choice("method", default_method, kCutMethod);
    c.snap_distance = r.number("snap_distance", c.snap_distance, 0, 0.5);
    c.sliver_volume = r.number("sliver_volume", c.sliver_volume, 0, 0.5);
    c.max_cells_per_tick = r.integer(
        "max_cells_per_tick", int(c.max_cells_per_tick), 0, std::numeric_limits<int>::max());
    c.max_model_growth = r.number("max_model_growth", c.max_model_growth, 0, 1e6);
    for_each_item(r, "sweeps", [&](const json& item, const std::string& p) {
        ObjectReader s(item, p);
        Sweep sw;
        sw.tick = s.integer("tick", 0, 0, std::numeric_limits<int>::max());
        const json& tris = s.get("triangles");
        if (!tris.is_array() || tris.empty())
            s.fail("triangles", "must be a non-empty array of triangles [[x,y,z],[x,y,z],[x,y,z]]");
        for (std::size_t t = 0; t < tris.size(); ++t) {
            const std::string tp = s.child("triangles") + "/" + std::to_string(t);
            if (!tris[t].is_array() || tris[t].size() != 3)
                throw SceneError(tp, "must be an array of 3 points");
            std::array<Vec3, 3> tri;
            for (std::size_t k = 0; k < 3; ++k)
                tri[k] = ObjectReader::parse_vec3(tris[t][k], tp + "/" + std::to_string(k), "m");
            sw.triangles.push_back(tri);
        }
        s.finish();
        c.sweeps.push_back(std::move(sw));
    });
    r.finish();
    return c;
}

Camera parse_camera(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Camera c;
    c.automatic = !(r.has("position") || r.has("target"));
    c.position = r.vec3("position", c.position, !c.automatic, "m");
    c.target = r.vec3("target", c.target, !c.automatic, "m");
    c.up = r.vec3("up", c.up);
    c.fov_deg = r.number("fov", c.fov_deg, 1, 170, false, "deg");
    r.finish();
    return c;
}
} // namespace

Scene parse_scene(const std::string& text, const std::string& directory) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        // parse_error, and out_of_range for a number that overflows a double (found by
        // tests/fuzz/fuzz_scene: "3e471" escaped as a non-polycut exception)
        throw SceneError("/", std::string("malformed JSON: ") + e.what());
    }
    ObjectReader r(j, "");
    Scene s;
    s.directory = directory;
    s.name = r.string("name", "");
    if (s.name.empty())
        r.fail("name", "is required (a short identifier)");
    s.description = r.string("description", "");
    s.geometry = parse_geometry(r.get("geometry"), r.child("geometry"));
    s.method = r.choice("method", s.method, kMethod);
    if (s.method == Method::Hex
        && !(s.geometry.kind == Geometry::Kind::Box && s.geometry.elements == Elements::Hex))
        r.fail("method", "\"hex\" needs a box geometry with \"elements\": \"hex\"");
    if (s.method == Method::Tet && s.geometry.kind == Geometry::Kind::Box
        && s.geometry.elements == Elements::Hex)
        r.fail("method",
            "\"tet\" needs tetrahedra; set /geometry/elements to \"tet\" or use method \"hex\"");
    if (r.has("basis"))
        s.basis = parse_basis(r.get("basis"), r.child("basis"));
    if (r.has("dg")) {
        if (s.method != Method::Dg)
            r.fail("dg", "applies to method \"dg\" only");
        s.dg = parse_dg(r.get("dg"), r.child("dg"));
    }
    if (s.method == Method::Mvc && s.basis.rule == basis::PolyRule::MonteCarlo)
        throw SceneError("/basis/rule",
            "\"monte_carlo\" integrates harmonic cells only; use "
            "\"heuristic\" or \"reference\" for mvc");
    s.material = parse_material(r.get("material"), r.child("material"));
    if (r.has("integrator"))
        s.integrator = parse_integrator(r.get("integrator"), r.child("integrator"));
    if (r.has("solver"))
        s.solver = parse_solver(r.get("solver"), r.child("solver"));
    for_each_item(r, "fixed", [&](const json& item, const std::string& p) {
        ObjectReader f(item, p);
        Fixed fx;
        if (f.has("node")) {
            if (f.has("box") || f.has("plane"))
                f.fail("node", "selects one node; give \"node\", \"box\" or \"plane\", not two");
            fx.at_node = true;
            fx.node = f.vec3("node", fx.node, true, "m");
        } else
            fx.where = parse_selector(f, "box", "plane");
        fx.components = parse_components(f);
        f.finish();
        s.fixed.push_back(fx);
    });
    for_each_item(r, "probes", [&](const json& item, const std::string& p) {
        ObjectReader pr(item, p);
        Probe probe;
        probe.name = pr.string("name", "");
        if (probe.name.empty())
            pr.fail("name", "is required");
        for (const auto& other : s.probes)
            if (other.name == probe.name)
                pr.fail("name", "duplicates probe \"" + probe.name + "\"");
        probe.point = pr.vec3("point", probe.point, true, "m");
        pr.finish();
        s.probes.push_back(probe);
    });
    if (r.has("loads")) {
        ObjectReader l(r.get("loads"), r.child("loads"));
        s.loads.gravity = l.vec3("gravity", s.loads.gravity, false, "m/s^2");
        for_each_item(l, "forces", [&](const json& item, const std::string& p) {
            ObjectReader f(item, p);
            Force force;
            force.force = f.vec3("force", force.force, true, "N");
            const bool at_point = f.has("point");
            const bool at_probe = f.has("probe");
            const bool region = f.has("box") || f.has("plane");
            if (int(at_point) + int(at_probe) + int(region) != 1)
                f.fail("", "needs exactly one of \"point\", \"probe\", \"box\" or \"plane\"");
            if (region) {
                force.kind = Force::Kind::Region;
                force.region = parse_selector(f, "box", "plane");
                force.distribution = f.choice("distribution", force.distribution, kDistribution);
            } else {
                force.kind = Force::Kind::Point;
                if (f.has("distribution"))
                    f.fail("distribution", "applies only to region forces (\"box\" or \"plane\")");
                if (at_point)
                    force.point = f.vec3("point", force.point, true, "m");
                else {
                    force.probe = f.string("probe", "");
                    bool found = false;
                    for (const auto& pr : s.probes)
                        found = found || pr.name == force.probe;
                    if (!found)
                        f.fail("probe", "names no probe (define it under /probes)");
                }
            }
            f.finish();
            s.loads.forces.push_back(force);
        });
        for_each_item(l, "pressure", [&](const json& item, const std::string& p) {
            ObjectReader f(item, p);
            Pressure pr;
            pr.pressure = f.number_required("pressure", -1e9, 1e9, false, "Pa");
            pr.region = parse_selector(f, "box", "plane");
            f.finish();
            s.loads.pressures.push_back(pr);
        });
        l.finish();
    }
    // DESIGN.md sec. 1: tets cut by face snapping (002), polyhedral methods by cell splitting
    // (000); a scene may override, except that snapping needs a pure tet mesh.
    s.cutting.method = s.method == Method::Tet ? CutMethod::Snap : CutMethod::Split;
    if (r.has("cutting"))
        s.cutting = parse_cutting(r.get("cutting"), r.child("cutting"), s.cutting.method);
    if (s.cutting.method == CutMethod::Snap && s.method != Method::Tet)
        throw SceneError(
            "/cutting/method", "\"snap\" (face snapping, seed 002) needs method \"tet\"");
    detail::parse_contact(r, s);
    if (r.has("camera"))
        s.camera = parse_camera(r.get("camera"), r.child("camera"));
    if (r.has("output")) {
        ObjectReader o(r.get("output"), r.child("output"));
        s.output.steps = o.integer("steps", s.output.steps, 0, 100000000);
        s.output.vtu_every = o.integer("vtu_every", s.output.vtu_every, 1, 100000000);
        o.finish();
    }
    r.finish();
    return s;
}

Scene load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw FileError(path, 0, "cannot open scene file");
    std::ostringstream ss;
    ss << in.rdbuf();
    const std::string dir = std::filesystem::path(path).parent_path().string();
    try {
        return parse_scene(ss.str(), dir);
    } catch (const SceneError& e) {
        throw SceneError(e.where(), e.problem() + " (in " + path + ")");
    }
}

bool selects(const Selector& s, const Vec3& X) {
    if (s.kind == Selector::Kind::Box)
        return (X.array() >= s.min.array() - s.tolerance).all()
            && (X.array() <= s.max.array() + s.tolerance).all();
    return std::abs((X - s.point).dot(s.normal)) <= s.tolerance;
}

} // namespace polycut::scene
