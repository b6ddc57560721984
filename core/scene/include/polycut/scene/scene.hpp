// Scene descriptions: what a scene file (JSON, docs/scenes.md) asks the simulator to build.
// Plain data with SI units; parsing lives in scene.cpp (nlohmann-json stays private there).
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace polycut::scene {

/// Where the mesh comes from.
struct Geometry {
    enum class Kind {
        Box,
        Implicit,
        SurfaceFile,
        MeshFile,
        RandomPlanes,
        ConvexHull,
        HexSlice,
        Octree
    };
    Kind kind = Kind::Box;
    // Box and RandomPlanes
    Vec3 origin = Vec3::Zero(); ///< min corner [m]
    Vec3 size = Vec3::Constant(0.1); ///< edge lengths [m]
    /// Box: 8 corners [m] in VTK hex order (bottom loop, then top); the grid is mapped onto
    /// this hexahedron trilinearly instead of [origin, origin + size] (empty: the plain box).
    /// Faces stay planar when each side of the hexahedron is planar (e.g. an extruded
    /// quadrilateral: Cook's membrane).
    std::vector<Vec3> corners;
    Eigen::Vector3i cells { 4, 4, 4 }; ///< blocks along x, y, z
    std::string elements = "tet"; ///< "tet" (split blocks) or "hex"
    std::string tet_split = "kuhn6"; ///< "kuhn6" or "five"
    int planes_per_cell = 0; ///< RandomPlanes: random planes cutting each block
    unsigned seed = 1; ///< RandomPlanes and meshing: random seed
    // Implicit; ConvexHull: "truncated_octahedron" or "" (explicit points)
    /// "sphere", "hollow_sphere", "ellipsoid", "capsule", "blob"; "truncated_octahedron"
    std::string shape;
    Vec3 center = Vec3::Zero(); ///< Implicit, ConvexHull shape: centre [m]
    Vec3 radii = Vec3::Constant(0.05); ///< semi-axes [m] (sphere, hollow_sphere: radii.x())
    double inner_radius = 0; ///< hollow_sphere: radius of the cavity [m], < radii.x()
    double length = 0.1; ///< capsule segment length [m]
    // Implicit and SurfaceFile: CGAL Mesh_3
    double cell_size = 0.01; ///< target tet size [m]
    /// Mesh_3 optimisers after refinement, any of "lloyd", "odt", "perturb", "exude" (run in
    /// that order); meshing::MeshingOptions
    std::vector<std::string> optimize { "perturb", "exude" };
    double sliver_bound = 0; ///< perturb/exude stop when every dihedral angle exceeds it [deg]
    /// Implicit and SurfaceFile: node numbering, "rcm" (reverse Cuthill-McKee, cells sorted by
    /// nodes; for locality) or "mesher" (as Mesh_3 inserted them)
    std::string node_order = "rcm";
    // SurfaceFile: treatment of a surface that is not a clean closed manifold (meshing::repair)
    std::string repair = "auto"; ///< "auto", "none", "pmp" or "wrap"
    std::string components = "union"; ///< "union", "largest" or "refuse"
    double wrap_alpha = 0; ///< Alpha_wrap_3 alpha [m]; 0: cell_size
    double wrap_offset = 0; ///< Alpha_wrap_3 offset [m]; 0: cell_size / 30
    // SurfaceFile and MeshFile
    std::string path; ///< resolved against the scene file's directory
    double scale = 1.0; ///< file units (ConvexHull: units of `points`) to metres
    // ConvexHull: one convex polyhedral cell whose nodes are the hull's corners
    std::vector<Vec3> points; ///< corners (>= 4, before `scale`), empty with a shape
    double edge_length = 0.05; ///< shape "truncated_octahedron": edge length [m]
    // HexSlice (003 sec. 10): a grid of cubes of edge cell_size [m] intersected with a closed
    // surface, the file `path` (with scale and repair) or the implicit shape above
    /// pieces of cut cubes below merge_fraction * cell_size^3 are merged into a neighbour
    /// [dimensionless, in [0, 1)]
    double merge_fraction = 0.1;
    /// implicit surface: edge size of its triangles (CGAL Mesh_3 facet size) [m]; 0: cell_size / 3
    double triangle_size = 0;
    /// Octree (issue 15 item 3): an adaptive octree of hex cells (meshing::Octree) embedding the
    /// object, which is the implicit `shape` (center, radii...), the surface file `path` (scale)
    /// or, with neither, the box [origin, origin + size]. `cell_size` is the base (coarsest)
    /// cell edge [m].
    struct OctreeRegion {
        Vec3 lo = Vec3::Zero(); ///< min corner [m]
        Vec3 hi = Vec3::Zero(); ///< max corner [m]
        double cell_size = 0; ///< largest cell edge inside [m]
    };
    struct OctreeSettings {
        std::string object = "box"; ///< "box", "implicit" or "surface_file" (from the keys)
        double surface_cell_size = 0; ///< largest cell the surface crosses [m]; 0: cell_size
        std::vector<OctreeRegion> regions; ///< boxes refined to their cell_size
        int max_depth = 6; ///< levels below the base cells (regions, surface, refinement)
        /// cells the surface crosses kept: "centre" (centre inside) or "cover" (all that may
        /// overlap the object)
        std::string keep = "centre";
        /// Stress-based refinement (001 sec. 8): after a step, cells whose largest absolute
        /// principal stress exceeds this [Pa] are split 1-to-8, down to max_depth; 0: never
        double refine_stress = 0;
    } octree;
};

/// Isotropic Hookean material with Rayleigh damping D = alpha M + beta K.
struct Material {
    double youngs_modulus = 1e4; ///< E [Pa]
    double poisson_ratio = 0.45; ///< nu, in [0, 0.5)
    double density = 1000; ///< rho [kg/m^3]
    double rayleigh_mass = 0; ///< alpha [1/s]
    double rayleigh_stiffness = 0; ///< beta [s]
};

/// Polyhedral basis options (methods mvc and harmonic).
struct Basis {
    std::string rule = "heuristic"; ///< mvc: "heuristic" (000 eq. 14-16) or "reference"
    int gauss_degree = 2; ///< degree of the Gauss rule on the centroid tetrahedralization
    double harmonic_xi = 0.1; ///< 001 eq. 12 kernel offset, relative to cell size
    /// Volumetric strain: "full" (the cell's quadrature), "mean_dilatation" (B-bar: one
    /// pressure per cell, no volumetric locking for hexes and polyhedra near nu = 0.5) or
    /// "nodal_average" (averaged nodal dilatation: one pressure per node, also for P1 tets)
    std::string volumetric = "full";
    /// dg: polynomial degree p of every cell's displacement field, 1 or 2
    int degree = 1;
};

/// Discontinuous Galerkin options (method dg, seed 003; docs/decisions/0020, 0021).
struct Dg {
    std::string flux = "ip"; ///< "ip" (symmetric interior penalty) or "bz" (Babuska-Zlamal)
    /// alpha of the face penalty eta_F = alpha p^2 |F| / min(|K-|, |K+|) [dimensionless, > 0]
    double penalty = 10.0;
    /// alpha of the Nitsche penalty on fixed (Dirichlet) faces [dimensionless, > 0]
    double dirichlet_penalty = 100.0;
    /// "full": (lambda + 2 mu) eta on the whole jump; "normal": 2 mu eta on the whole jump plus
    /// lambda eta on its normal part (removes volumetric locking near nu = 0.5)
    std::string lambda_penalty = "full";
    /// Stress-based refinement (003 sec. 10): after a step, hex cells whose largest absolute
    /// principal stress exceeds this are split 1-to-8 [Pa]; 0 = off
    double refine_stress = 0;
    /// times a cell's lineage may be split (>= 1)
    int refine_levels = 1;
};

struct Integrator {
    std::string type = "implicit_euler"; ///< "static", "implicit_euler", "semi_implicit_euler"
    double dt = 0.01; ///< time step [s]
    bool corotated = true; ///< corotational (true) or linear elasticity
    std::string static_mode = "newton"; ///< static + corotated: "newton" or "fixed_point"
    double tolerance = 1e-8; ///< static: stop at ||r|| <= tol ||f_ext||
    int max_iterations = 100; ///< static: outer iterations
    /// Threads for assembly and the solver's matrix passes (1 = serial). Results are
    /// deterministic for a given count; different counts agree to round-off.
    int threads = 1;
    /// implicit_euler: assemble the corotated stiffness every k steps, reuse it in between
    int stiffness_every = 1;
    /// implicit_euler: redo a step that gains energy as two half steps (up to 16 substeps;
    /// integrate::IntegratorOptions::energy_guard)
    bool energy_guard = false;
};

struct Solver {
    std::string type = "pcg"; ///< "cholmod", "pcg" or "cg_relaxation" (002 sec. 3.1)
    /// pcg: "jacobi", "block_jacobi", "cell_block_jacobi" (dg: one block per cell),
    /// "lagged_cholesky", "amg" (hypre BoomerAMG), "two_level" (dg: cell block Jacobi plus a
    /// P1 coarse space on the nodes, docs/decisions/0024)
    std::string preconditioner = "jacobi";
    double tolerance = 1e-6; ///< relative residual
    double load_tolerance = 0; ///< residual floor as a fraction of h ||f_ext|| (0 = off)
    int max_iterations = 2000;
    /// lagged_cholesky, amg: refactor (set up again) every k solves (0 = on demand)
    int refactor_every = 0;
    /// lagged_cholesky, amg: ...or when a solve needed more PCG iterations than this
    int refactor_iterations = 50;
    /// implicit_euler with pcg / cg_relaxation: initial guess of the velocity increment dv,
    /// "previous" (dv_{n-1}) or "extrapolated" (2 dv_{n-1} - dv_{n-2})
    std::string warm_start = "previous";
    /// amg: BoomerAMG set-up (solve::AmgOptions; defaults there)
    double amg_strong_threshold = 0.5; ///< strength threshold theta in (0, 1)
    int amg_aggressive_levels = 1; ///< levels coarsened aggressively
    int amg_interpolation_max_elements = 4; ///< interpolation entries per row (0 = all)
    bool amg_rigid_body_modes = false; ///< interpolate the rigid rotations too (GM-2)
    bool amg_node_blocks = false; ///< 3x3 node-block smoothing of the finest level
    /// solves between starting a requested set-up on a worker thread and installing it (0 = set
    /// up in the foreground, blocking that step)
    int amg_background_solves = 8;
};

/// Selects nodes by rest position.
struct Selector {
    enum class Kind { Box, Plane };
    Kind kind = Kind::Box;
    Vec3 min = Vec3::Zero(), max = Vec3::Zero(); ///< Box [m]
    Vec3 point = Vec3::Zero(); ///< Plane: a point on it [m]
    Vec3 normal = Vec3::UnitX(); ///< Plane: normal (normalized on load)
    double tolerance = 1e-9; ///< Plane: distance [m]; Box: padding [m]
};

/// Fixed nodes: all three displacement components, or a subset ("x", "yz", ...), of the nodes a
/// region selects or of the one node nearest a point (3-2-1 supports of a free body: no
/// reactions under a self-equilibrated load such as a closed pressure surface).
struct Fixed {
    Selector where;
    bool at_node = false; ///< true: the node nearest `node` instead of the region `where`
    Vec3 node = Vec3::Zero(); ///< rest-space point [m] (at_node)
    std::array<bool, 3> components { true, true, true };
};

/// A force on the tissue: at the node nearest a point or a probe, or a total force spread over
/// the nodes of a region (uniform per node, or weighted by boundary area, a traction).
struct Force {
    enum class Kind { Point, Region };
    Kind kind = Kind::Point;
    Vec3 point = Vec3::Zero(); ///< Point: rest-space location [m]
    std::string probe; ///< Point: name of a probe instead of `point`
    Selector region; ///< Region
    std::string distribution = "area"; ///< Region: "area" or "uniform"
    Vec3 force = Vec3::Zero(); ///< total force [N]
};

/// A pressure on the boundary faces inside a region: traction -p n (n the outward normal of
/// the tissue), so a positive p pushes into the tissue. Dead load: the rest-space faces.
struct Pressure {
    Selector region; ///< boundary faces whose nodes it all selects
    double pressure = 0; ///< p [Pa]
};

struct Loads {
    Vec3 gravity = Vec3::Zero(); ///< [m/s^2]
    std::vector<Force> forces;
    std::vector<Pressure> pressures;
};

struct Probe {
    std::string name;
    Vec3 point = Vec3::Zero(); ///< rest-space location [m]
};

/// A scalpel sweep applied at a given tick (headless cut scenes).
struct Sweep {
    long tick = 0; ///< tick at which it arrives
    std::vector<std::array<Vec3, 3>> triangles; ///< world-space sweep triangles [m]
};

struct Cutting {
    std::string method = "split"; ///< "split" (cell splitting, 000 sec. 5; default except for tet)
                                  ///< or "snap" (face snapping, 002; default for tet)
    /// node snapping distance, relative to the local cell thickness; larger than the cutter's
    /// own default (CutOptions::snap, for exact rest-space cuts) because scene blades reach rest
    /// space through a fit of the deformed body (docs/scenes.md)
    double snap_distance = 1e-2;
    double sliver_volume
        = 1e-3; ///< cells below this fraction of their largest interior neighbour are merged
    /// cells the cuts of one tick may change (split or rewrite) before the remaining sweep
    /// triangles wait for the next tick (a count, so replays cut the same); 0: no limit
    Index max_cells_per_tick = 600;
    std::vector<Sweep> sweeps;
};

struct Camera {
    bool automatic = true;
    Vec3 position = Vec3::Zero(), target = Vec3::Zero(), up = Vec3::UnitZ(); ///< [m]
    double fov_deg = 35;
};

struct Output {
    long steps = 100; ///< dynamic scenes: default number of steps for the runner
    long vtu_every = 10; ///< write every k-th frame with --vtu
};

/// A rigid obstacle the tissue cannot enter (penalty contact, issue 15 item 1; docs/scenes.md
/// "obstacles"). Fixed in the world.
struct Obstacle {
    enum class Kind { Plane, Box, Sphere, Capsule, Mesh };
    Kind kind = Kind::Plane;
    std::string name; ///< optional label (reports)
    /// Plane: a point on it; box, sphere: the centre; mesh: the translation [m]
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ(); ///< Plane: unit normal pointing out of the solid side
    Vec3 size = Vec3::Constant(0.1); ///< Box: edge lengths [m]
    /// Box and mesh: rotation as an axis-angle vector (axis times angle) [rad]
    Vec3 rotation = Vec3::Zero();
    double radius = 0.01; ///< Sphere, capsule [m]
    Vec3 a = Vec3::Zero(), b = Vec3::UnitZ(); ///< Capsule: axis endpoints [m]
    std::string path; ///< Mesh: closed surface file, relative to the scene file
    double scale = 1.0; ///< Mesh: file units to metres
    /// Penalty stiffness [N/m^3] and Coulomb friction coefficient of this obstacle; absent:
    /// the scene's `contact` values
    std::optional<double> stiffness, friction;
};

/// A tool the scene moves itself along keyframes (docs/scenes.md "tools"): what a client
/// would do with tool_create / tool_move, built into the scene so the runner and a recording
/// replay it without a client.
struct ScriptedTool {
    std::string shape = "sphere"; ///< "sphere", "capsule" or "blade" (sim::ToolSpec)
    double radius = 0.005; ///< sphere, capsule [m]
    double length = 0.05; ///< capsule axis length [m]
    Vec3 size = Vec3(0.03, 0.01, 0.001); ///< blade edge lengths [m]
    std::optional<double> stiffness, friction; ///< absent: the scene's `contact` values
    struct Key {
        double t = 0; ///< simulated time [s], increasing along the keys
        Vec3 position = Vec3::Zero(); ///< tool frame origin [m]
        Eigen::Vector4d orientation { 1, 0, 0, 0 }; ///< unit quaternion [w, x, y, z]
    };
    /// Poses in time: linear between keys (orientations slerped), held before the first and
    /// after the last
    std::vector<Key> keys;
};

/// Contact settings (docs/scenes.md "contact"). Absent values take contact::ContactParams'
/// defaults (the one place they are set).
struct Contact {
    std::optional<double> stiffness; ///< penalty pressure per penetration depth [N/m^3]
    std::optional<double> friction; ///< Coulomb coefficient (dimensionless)
    std::optional<double> slip_velocity; ///< friction's regularization speed [m/s]
    /// Contact between the pieces a cut separated: penalty stiffness [N/m^3]; 0 = off
    double self_stiffness = 0;
};

/// A detailed surface embedded in the simulation mesh (docs/scenes.md "embedded", issue 15
/// item 2): streamed and rendered instead of the mesh's boundary, sampled by contact.
struct Embedded {
    std::string path; ///< surface file (OFF/OBJ/STL/PLY) relative to the scene file
    double scale = 1.0; ///< file units to metres
};

/// A whole scene.
struct Scene {
    std::string name;
    std::string description;
    std::string directory; ///< directory of the scene file (for relative paths); "" inline
    Geometry geometry;
    std::string method = "tet"; ///< "tet", "hex", "mvc", "harmonic", "dg"
    Basis basis;
    Dg dg; ///< method dg only
    Material material;
    Integrator integrator;
    Solver solver;
    std::vector<Fixed> fixed;
    Loads loads;
    std::vector<Probe> probes;
    Cutting cutting;
    std::vector<Obstacle> obstacles;
    std::vector<ScriptedTool> tools;
    Contact contact;
    std::optional<Embedded> embedded;
    Camera camera;
    Output output;
};

/// Parses a scene from JSON text. Throws polycut::SceneError whose where() is a JSON pointer
/// to the offending field, with what is allowed. Unknown keys are errors. `directory` is used
/// to resolve relative file paths.
Scene parse_scene(const std::string& json_text, const std::string& directory = "");

/// Reads and parses a scene file. Throws FileError if unreadable, SceneError if invalid.
Scene load_scene(const std::string& path);

/// True when the selector picks rest position X.
bool selects(const Selector& s, const Vec3& X);

} // namespace polycut::scene
