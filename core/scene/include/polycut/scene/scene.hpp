// Scene descriptions: what a scene file (JSON, docs/scenes.md) asks the simulator to build.
// Plain data with SI units; parsing lives in scene.cpp (nlohmann-json stays private there).
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/options/basis.hpp"
#include "polycut/options/dg.hpp"
#include "polycut/options/elasticity.hpp"
#include "polycut/options/integrate.hpp"
#include "polycut/options/solve.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace polycut::scene {

// Every string option of a scene file is one of these enums, parsed once by parse_scene() (an
// unknown name is a SceneError naming the JSON pointer and the accepted names). Options that a
// module owns use the module's own enum and default (the options layer, docs/decisions/0051);
// the enums below are the scene's own vocabulary. to_string() gives the scene-file name.

/// Element method (DESIGN.md sec. 1).
enum class Method { Tet, Hex, Mvc, Harmonic, Dg };
/// Cells of a box grid.
enum class Elements { Tet, Hex };
/// How a box block is split into tets.
enum class TetSplit { Kuhn6, Five };
/// An implicit shape or a named convex cell (geometry "implicit", "octree", "hex_slice",
/// "convex_hull"); None when the geometry has no shape.
enum class Shape { None, Sphere, HollowSphere, Ellipsoid, Capsule, Blob, TruncatedOctahedron };
/// Node numbering of a CGAL-meshed geometry.
enum class NodeOrder { Rcm, Mesher };
/// Treatment of a surface file that is not a clean closed manifold (meshing::RepairMode).
enum class Repair { Auto, None, Pmp, Wrap };
/// Which connected components of a surface file are meshed (meshing::ComponentsMode).
enum class Components { Union, Largest, Refuse };
/// What an octree geometry embeds.
enum class OctreeObject { Box, Implicit, SurfaceFile };
/// Octree cells the surface crosses that are kept.
enum class OctreeKeep { Centre, Cover };
/// The linear solver family; with Pcg, the preconditioner picks the variant.
enum class SolverType { Cholmod, Pcg, CgRelaxation };
enum class Preconditioner { Jacobi, BlockJacobi, CellBlockJacobi, LaggedCholesky, Amg, TwoLevel };
/// Initial guess of an implicit step's velocity increment.
enum class WarmStart { Previous, Extrapolated, Projected };
/// How a region force is spread over its nodes.
enum class Distribution { Area, Uniform };
/// Cutting method: cell splitting (000) or face snapping (002, tet only).
enum class CutMethod { Split, Snap };
/// A scripted tool's shape.
enum class ToolShape { Sphere, Capsule, Blade };

const char* to_string(Method);
const char* to_string(Elements);
const char* to_string(TetSplit);
const char* to_string(Shape);
const char* to_string(NodeOrder);
const char* to_string(Repair);
const char* to_string(Components);
const char* to_string(OctreeObject);
const char* to_string(OctreeKeep);
const char* to_string(SolverType);
const char* to_string(Preconditioner);
const char* to_string(WarmStart);
const char* to_string(Distribution);
const char* to_string(CutMethod);
const char* to_string(ToolShape);
const char* to_string(basis::PolyRule);
const char* to_string(basis::VolumetricRule);
const char* to_string(dg::Flux);
const char* to_string(dg::LambdaPenalty);
const char* to_string(integrate::IntegratorKind);
/// "newton" or "fixed_point" (Linear: "linear", which a scene file cannot name: it is
/// corotated false)
const char* to_string(integrate::StaticMode);

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
    Elements elements = Elements::Tet; ///< tets (split blocks) or hexes
    TetSplit tet_split = TetSplit::Kuhn6;
    int planes_per_cell = 0; ///< RandomPlanes: random planes cutting each block
    unsigned seed = 1; ///< RandomPlanes and meshing: random seed
    /// Implicit (and Octree, HexSlice): sphere, hollow_sphere, ellipsoid, capsule, blob;
    /// ConvexHull: truncated_octahedron or None (explicit points)
    Shape shape = Shape::None;
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
    /// Implicit and SurfaceFile: node numbering, rcm (reverse Cuthill-McKee, cells sorted by
    /// nodes; for locality) or mesher (as Mesh_3 inserted them)
    NodeOrder node_order = NodeOrder::Rcm;
    // SurfaceFile: treatment of a surface that is not a clean closed manifold (meshing::repair)
    Repair repair = Repair::Auto;
    Components components = Components::Union;
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
        OctreeObject object = OctreeObject::Box; ///< from the keys (shape, path or neither)
        double surface_cell_size = 0; ///< largest cell the surface crosses [m]; 0: cell_size
        std::vector<OctreeRegion> regions; ///< boxes refined to their cell_size
        int max_depth = 6; ///< levels below the base cells (regions, surface, refinement)
        /// cells the surface crosses kept: Centre (centre inside) or Cover (all that may
        /// overlap the object)
        OctreeKeep keep = OctreeKeep::Centre;
        /// Stress-based refinement (001 sec. 8): after a step, cells whose largest absolute
        /// principal stress exceeds this [Pa] are split 1-to-8, down to max_depth; 0: never
        double refine_stress = 0;
    } octree;
};

/// Isotropic Hookean material with Rayleigh damping D = alpha M + beta K: the module's type,
/// defaults and all (youngs_modulus is required in a scene file).
using Material = elasticity::Material;

/// Polyhedral basis options (methods mvc and harmonic); defaults from basis::BasisOptions.
struct Basis {
    /// mvc: Heuristic (000 eq. 14-16) or Reference; harmonic: Reference (Heuristic, meaningful
    /// for mean value cells only, means Reference there) or MonteCarlo
    basis::PolyRule rule = basis::BasisOptions {}.rule;
    /// degree of the Gauss rule on the centroid tetrahedralization
    int gauss_degree = basis::BasisOptions {}.gauss_degree;
    /// 001 eq. 12 kernel offset, relative to cell size [dimensionless]
    double harmonic_xi = basis::BasisOptions {}.harmonic_xi;
    /// Volumetric strain: Full (the cell's quadrature), MeanDilatation (B-bar: one pressure per
    /// cell, no volumetric locking for hexes and polyhedra near nu = 0.5) or NodalAverage
    /// (averaged nodal dilatation: one pressure per node, also for P1 tets)
    basis::VolumetricRule volumetric = basis::BasisOptions {}.volumetric;
    /// dg: polynomial degree p of every cell's displacement field, 1 or 2
    int degree = dg::DgOptions {}.degree;
};

/// Discontinuous Galerkin options (method dg, seed 003; docs/decisions/0020, 0021); defaults
/// from dg::DgOptions.
struct Dg {
    dg::Flux flux = dg::DgOptions {}.flux; ///< symmetric interior penalty or Babuska-Zlamal
    /// alpha of the face penalty eta_F = alpha p^2 |F| / min(|K-|, |K+|) [dimensionless, > 0]
    double penalty = dg::DgOptions {}.penalty;
    /// alpha of the Nitsche penalty on fixed (Dirichlet) faces [dimensionless, > 0]
    double dirichlet_penalty = dg::DgOptions {}.dirichlet_penalty;
    /// Full: (lambda + 2 mu) eta on the whole jump; Normal: 2 mu eta on the whole jump plus
    /// lambda eta on its normal part (removes volumetric locking near nu = 0.5)
    dg::LambdaPenalty lambda_penalty = dg::DgOptions {}.lambda_penalty;
    /// Stress-based refinement (003 sec. 10): after a step, hex cells whose largest absolute
    /// principal stress exceeds this are split 1-to-8 [Pa]; 0 = off
    double refine_stress = 0;
    /// times a cell's lineage may be split (>= 1)
    int refine_levels = 1;
};

/// Time integration; defaults from integrate::IntegratorOptions.
struct Integrator {
    integrate::IntegratorKind type = integrate::IntegratorOptions {}.kind;
    double dt = integrate::IntegratorOptions {}.dt; ///< time step [s]
    /// corotational (true) or linear elasticity
    bool corotated = integrate::IntegratorOptions {}.force_mode == elasticity::ForceMode::Corotated;
    /// static + corotated: CorotatedNewton ("newton") or CorotatedFixedPoint ("fixed_point");
    /// a static linear scene (corotated false) runs StaticMode::Linear whatever this says
    integrate::StaticMode static_mode = integrate::IntegratorOptions {}.static_mode;
    /// static: stop at ||r|| <= tol ||f_ext|| [dimensionless]
    double tolerance = integrate::IntegratorOptions {}.static_tolerance;
    int max_iterations = integrate::IntegratorOptions {}.static_max_iterations; ///< static
    /// Threads for assembly and the solver's matrix passes (1 = serial). Results are
    /// deterministic for a given count; different counts agree to round-off.
    int threads = integrate::IntegratorOptions {}.threads;
    /// implicit_euler: assemble the corotated stiffness every k steps, reuse it in between
    int stiffness_every = integrate::IntegratorOptions {}.stiffness_every;
    /// implicit_euler: redo a step that gains energy as two half steps (up to 16 substeps;
    /// integrate::IntegratorOptions::energy_guard)
    bool energy_guard = integrate::IntegratorOptions {}.energy_guard;
};

/// Linear solver; defaults from integrate::SolverOptions (whose kind PcgJacobi is type Pcg
/// with preconditioner Jacobi) and solve::AmgOptions.
struct Solver {
    SolverType type = SolverType::Pcg; ///< cholmod, pcg or cg_relaxation (002 sec. 3.1)
    /// pcg: jacobi, block_jacobi, cell_block_jacobi (dg: one block per cell), lagged_cholesky,
    /// amg (hypre BoomerAMG), two_level (dg: cell block Jacobi plus a P1 coarse space on the
    /// nodes, docs/decisions/0024)
    Preconditioner preconditioner = Preconditioner::Jacobi;
    /// relative residual [dimensionless]
    double tolerance = integrate::SolverOptions {}.relative_tolerance;
    /// residual floor as a fraction of h ||f_ext|| (0 = off) [dimensionless]
    double load_tolerance = integrate::SolverOptions {}.load_tolerance;
    int max_iterations = integrate::SolverOptions {}.max_iterations;
    /// PCG iterations after which a solve stops and the step takes its iterate (0 = off)
    int iteration_budget = integrate::SolverOptions {}.iteration_budget;
    /// lagged_cholesky, amg: refactor (set up again) every k solves (0 = on demand)
    int refactor_every = integrate::SolverOptions {}.refactor_every;
    /// lagged_cholesky, amg: ...or when a solve needed more PCG iterations than this
    int refactor_iterations = integrate::SolverOptions {}.refactor_iterations;
    /// implicit_euler with pcg / cg_relaxation: initial guess of the velocity increment dv,
    /// Previous (dv_{n-1}), Extrapolated (2 dv_{n-1} - dv_{n-2}) or, with pcg, Projected (the
    /// Galerkin projection onto the last start_vectors solutions)
    WarmStart warm_start = integrate::IntegratorOptions {}.extrapolate_warm_start
        ? WarmStart::Extrapolated
        : WarmStart::Previous;
    /// warm_start projected: solutions kept for the projection (>= 1)
    int start_vectors = integrate::kProjectedStartVectors;
    /// amg: BoomerAMG set-up (solve::AmgOptions; defaults there)
    double amg_strong_threshold = solve::AmgOptions {}.strong_threshold; ///< theta in (0, 1)
    int amg_aggressive_levels = solve::AmgOptions {}.aggressive_levels;
    /// interpolation entries per row (0 = all)
    int amg_interpolation_max_elements = solve::AmgOptions {}.interpolation_max_elements;
    /// unknowns of the coarsest level, solved directly
    int amg_max_coarse_size = solve::AmgOptions {}.max_coarse_size;
    bool amg_rigid_body_modes = solve::AmgOptions {}.rigid_body_modes; ///< GM-2 rotations too
    bool amg_node_blocks = solve::AmgOptions {}.node_blocks; ///< 3x3 node-block smoothing
    /// solves between starting a requested set-up on a worker thread and installing it (0 = set
    /// up in the foreground, blocking that step). The one scene default that differs from its
    /// module's on purpose (docs/decisions/0051): solve::AmgOptions sets up in the foreground
    /// (what a bare solver and the benchmarks want); a scene runs in a loop whose tick a
    /// ~100 ms set-up would stall, so scenes hand it to a worker.
    int amg_background_solves = 8;
    /// one thread for the step while a background set-up runs (solve::AmgOptions)
    bool amg_background_serial = solve::AmgOptions {}.background_serial;
    /// solves after the last cut before a requested set-up starts (solve::AmgOptions)
    int amg_refresh_delay = solve::AmgOptions {}.refresh_delay;
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
    Distribution distribution = Distribution::Area; ///< Region: by boundary area or per node
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
    /// Split (cell splitting, 000 sec. 5; default except for tet) or Snap (face snapping, 002;
    /// default for tet)
    CutMethod method = CutMethod::Split;
    /// node snapping distance, relative to the local cell thickness; larger than the cutter's
    /// own default (CutOptions::snap, for exact rest-space cuts) because scene blades reach rest
    /// space through a fit of the deformed body (docs/scenes.md)
    double snap_distance = 1e-2;
    double sliver_volume
        = 1e-3; ///< cells below this fraction of their largest interior neighbour are merged
    /// cells the cuts of one tick may change (split or rewrite) before the remaining sweep
    /// triangles wait for the next tick (a count, so replays cut the same); 0: no limit
    Index max_cells_per_tick = 600;
    /// The cells' element matrices (sum of (3 nodes)^2) may grow to at most this many times the
    /// uncut mesh's; a cut past it is undone (before the model follows it) and reported. Dense
    /// sweeps (a soup of triangles) make large cells that slow every later step. 0: no limit
    double max_model_growth = 4;
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
    ToolShape shape = ToolShape::Sphere; ///< sim::ToolSpec
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
    Method method = Method::Tet;
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

/// Scene-file names of the geometry and obstacle types.
const char* to_string(Geometry::Kind);
const char* to_string(Obstacle::Kind);

/// Parses a scene from JSON text. Throws polycut::SceneError whose where() is a JSON pointer
/// to the offending field, with what is allowed. Unknown keys are errors. `directory` is used
/// to resolve relative file paths.
Scene parse_scene(const std::string& json_text, const std::string& directory = "");

/// Reads and parses a scene file. Throws FileError if unreadable, SceneError if invalid.
Scene load_scene(const std::string& path);

/// True when the selector picks rest position X.
bool selects(const Selector& s, const Vec3& X);

} // namespace polycut::scene
