// sim::Simulation, the facade the server, the runner and the tests use (DESIGN.md sec. 2): built
// from a scene, it steps, applies forces, grabs and cuts, and hands out the surface. step()
// never throws; bad input to the other calls throws polycut::InputError and changes nothing.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/build_report.hpp"
#include "polycut/sim/tools.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace polycut::sim {

/// What one tick did.
struct StepReport {
    long tick = 0; ///< tick number after this step (first step -> 1)
    double sim_time = 0; ///< simulated time after this step [s]
    double step_ms = 0; ///< wall time of the whole step [ms]
    double assembly_ms = 0; ///< assembly of K and forces [ms]
    double solve_ms = 0; ///< linear solves [ms]
    double cut_ms = 0; ///< cuts applied at this tick, incl. cell set-up [ms]
    int solver_iterations = 0; ///< PCG iterations (0 for a direct solve)
    /// PCG stopped at `solver.iteration_budget` (`residual` says how far from the tolerance)
    bool solver_budget_reached = false;
    int newton_iterations = 0; ///< static scenes: outer iterations
    double residual = 0; ///< relative residual of the last solve
    bool topology_changed = false;
    bool rolled_back = false; ///< the step failed and the state was restored
    /// The step failed right after a cut: the cuts applied since the previous step were undone
    /// with it (mesh, state and loads as before them); `warnings` says why.
    bool cut_undone = false;
    /// Octree geometry with refine_stress: cells split 1-to-8 after this step (001 sec. 8),
    /// and the mechanical energy (Energy::total) of the state just before and just after the
    /// transfer to the refined mesh [J] (the "pop" a refinement causes).
    int cells_refined = 0;
    double refine_energy_before = 0, refine_energy_after = 0;
    std::vector<std::string> warnings;
};

/// A force on the tissue, spread over the nodes within `radius` of a world-space point.
struct ForceSpec {
    Vec3 point = Vec3::Zero(); ///< world-space point [m]
    Vec3 force = Vec3::Zero(); ///< total force [N]
    double radius = 0.005; ///< [m]; the nearest node is used if none lies within
    double duration = 0; ///< [s]; 0 = until removed
};

/// A grab: material points near `point` pulled toward `target` by a spring.
struct GrabSpec {
    Vec3 point = Vec3::Zero(); ///< world-space point picked [m]
    double stiffness = 50; ///< spring stiffness [N/m]
    double radius = 0.005; ///< [m]
};

/// Surface for streaming and rendering.
struct Surface {
    std::uint64_t topology_version = 0;
    std::vector<float> positions; ///< (#V x 3) world positions [m]
    std::vector<std::uint32_t> triangles; ///< (#T x 3)
    std::vector<std::uint8_t> tags; ///< (#T) 1 skin, 2 cut
};

/// What a cut did (the typed result of core/cut's pipeline, docs/decisions/0010).
struct CutSummary {
    enum class Status {
        Applied, ///< every triangle was cut, skipped, or missed the tissue
        /// The tick's budget of changed cells (scene cutting.max_cells_per_tick) was reached:
        /// the last `triangles_deferred` triangles were not looked at; pass them again after
        /// the next step().
        Deferred,
        /// Refused before anything changed: triangle `rejected_triangle` (corner
        /// `rejected_corner`, -1 for the whole triangle) is not a usable sweep triangle.
        Rejected,
        /// The cutter or the model could not carry the cut out: it was undone, nothing changed.
        Failed,
    };
    Status status = Status::Applied;
    int rejected_triangle = -1; ///< Rejected: index into the call's triangles
    int rejected_corner = -1; ///< Rejected: corner 0-2, or -1
    std::string reason; ///< Rejected and Failed: what is wrong
    int triangles_deferred = 0; ///< Deferred: trailing triangles not cut
    bool ok() const { return status == Status::Applied || status == Status::Deferred; }
    int triangles_applied = 0;
    /// Sweep triangles too small to cut anything at the tissue's scale (area below 2e-10 L^2
    /// or altitude below 2e-10 L, L the tissue's diagonal), in world or rest space: skipped.
    int triangles_skipped = 0;
    /// Rest-space area of the applied triangles inside the uncut tissue [m^2].
    double swept_area = 0;
    /// Inverted tets around the sweep (cut::CutResult::inverted_cells): the body folded under
    /// the blade. The next step's report warns about it.
    int inverted_cells = 0;
    int cells_split = 0;
    int nodes_added = 0;
    int cells_before = 0, cells_after = 0;
    bool topology_changed = false;
    /// Static scenes: pieces the cut freed from every fixed node, each now fixed at one of its
    /// boundary faces (as 002 sec. 3.3 does) so the static problem stays well posed.
    int pieces_fixed = 0;
    /// Dynamic scenes: fragments of at most 64 cells the cut freed from every fixed node, held
    /// where they are (their nodes fixed) instead of falling for ever (docs/scenes.md).
    int fragments_pinned = 0;
    double cut_ms = 0;
};

/// cut / (2 swept), 0 before anything was swept (issue 12 item 4).
inline double cut_completeness(double cut_area, double swept_area) {
    return swept_area > 0 ? cut_area / (2 * swept_area) : 0.0;
}

/// Mesh figures the runner reports.
struct MeshStats {
    Index nodes = 0, cells = 0, boundary_triangles = 0, components = 0;
    double rest_volume = 0; ///< [m^3]
    bool surface_closed = false;
    /// Rest-space area of the Cut faces, both lips [m^2].
    double cut_area = 0;
    /// Rest-space area the blade swept inside the uncut tissue, summed over the cuts applied
    /// (a re-cut over an earlier cut counts again) [m^2].
    double swept_area = 0;
    /// Rest-space area the blade swept inside the uncut tissue in cuts that were undone (a cut
    /// that failed, or the cuts a failed step took back) [m^2]: uncut, but swept.
    double swept_area_undone = 0;
    /// What a step costs over the uncut mesh's (the cells' element matrix entries, the sum of
    /// (3 nodes)^2, a cell other than a tet weighted 4: what assembling and each PCG iteration
    /// grow with; cutting.max_model_growth bounds it); 1 uncut.
    double model_growth = 1;
    /// cut_area / (2 (swept_area + swept_area_undone)): 1 when the cut opened exactly what the
    /// blade swept (issue 12 item 4); 0 before any cut.
    double completeness() const {
        return cut_completeness(cut_area, swept_area + swept_area_undone);
    }
};

/// The cut figures of MeshStats alone (Simulation::cut_areas, O(faces)).
struct CutAreas {
    double cut_area = 0; ///< as MeshStats::cut_area [m^2]
    double swept_area = 0; ///< as MeshStats::swept_area [m^2]
    double swept_area_undone = 0; ///< as MeshStats::swept_area_undone [m^2]
    double completeness() const {
        return cut_completeness(cut_area, swept_area + swept_area_undone);
    }
};

/// Mechanical energy of the current state [J] (issue 17 item 4: with damping and no input, the
/// total does not grow).
struct Energy {
    double kinetic = 0; ///< 1/2 v^T M v
    double elastic = 0; ///< the model's strain energy (corotated or linear, as the scene says)
    double gravity = 0; ///< potential of gravity relative to rest, -sum_i m_i g . (x_i - X_i)
    double total() const { return kinetic + elastic + gravity; }
};

/// The embedded surface (scene key `embedded`) and what the last cut did to it.
struct EmbeddedStats {
    std::size_t vertices = 0, triangles = 0; ///< of the published surface, lips included
    std::size_t lip_triangles = 0; ///< tag 2 triangles (both sides of every cut)
    bool split = true; ///< the skin is split along the cuts (false after a CGAL failure)
    double embed_ms = 0; ///< wall time of the last (re-)embedding after a topology change [ms]
    double split_ms = 0; ///< of which splitting along the cut [ms]
    double corefine_ms = 0; ///< of which CGAL corefinement [ms]
    std::size_t patch_triangles = 0; ///< skin triangles the last split corefined
    std::size_t cut_triangles = 0; ///< cut-surface triangles it corefined them with
    std::size_t reembedded = 0; ///< vertices the last update embedded again
    bool full = false; ///< the last update embedded the whole surface anew (load, undo)
};

/// Sizes of what a scene built, for cost reports (issue 17 item 1).
struct ModelStats {
    Index dofs = 0; ///< 3 x the nodes used by cells
    Index free_dofs = 0; ///< unknowns of the linear systems (fixed DOFs eliminated)
    Index nonzeros = 0; ///< stored entries of the reduced stiffness (both triangles)
    Index tets = 0, hexes = 0, polyhedra = 0; ///< cells by kind (P1, Q1, polyhedral basis)
};

/// What CGAL meshing reported when the scene's geometry was meshed (geometry "surface_file" or
/// "implicit"): the repair of the surface and the quality of the tets (meshing::RepairReport and
/// meshing::TetQuality, copied so that this header stays free of the meshing module).
struct MeshingSummary {
    /// False for geometry that is not meshed by CGAL (box, random_planes, mesh_file,
    /// convex_hull): every other field keeps its default.
    bool meshed = false;
    std::string source; ///< "surface_file" or "implicit"

    // Repair (surface_file only; implicit shapes need none): repair.hpp
    bool has_repair = false; ///< true for surface_file
    std::string repair_mode; ///< what the scene asked: "auto", "none", "pmp" or "wrap"
    std::string repair_applied; ///< what was done: "none", "pmp", "wrap" or "pmp+wrap"
    std::string repair_summary; ///< one line: RepairReport::summary()
    Index faces_in = 0, faces_out = 0; ///< triangles before and after the repair
    Index holes_filled = 0, holes_unfilled = 0;
    Index self_intersections_in = 0; ///< intersecting face pairs found
    Index self_intersections_out = 0; ///< ... left after PMP's removal
    Index components_in = 0, components_out = 0;
    bool wrapped = false; ///< the surface was replaced by an Alpha_wrap_3 wrap
    double volume_in = 0, volume_out = 0; ///< enclosed volume before and after [m^3]
    double volume_change = 0; ///< volume_out / volume_in - 1
    double repair_ms = 0; ///< wall time of the repair [ms]

    // Quality of the tets (quality.hpp)
    Index tets = 0;
    double min_dihedral_deg = 0; ///< smallest dihedral angle [deg]
    double max_dihedral_deg = 0; ///< largest dihedral angle [deg]
    /// Radius ratio 3 r_in / r_circ (1 regular, 0 flat): minimum, 1st percentile, median.
    double radius_ratio_min = 0, radius_ratio_p1 = 0, radius_ratio_p50 = 0;
    Index slivers = 0; ///< tets with a dihedral angle below sliver_dihedral_deg
    double sliver_dihedral_deg = 0; ///< the sliver threshold [deg]
    bool has_slivers = false; ///< slivers > 0: the scene should be remeshed
    std::string quality_summary; ///< one line: meshing::to_string(TetQuality)

    double mesh_ms = 0; ///< wall time of CGAL Mesh_3 with its optimisers [ms]
    double total_ms = 0; ///< wall time of the whole meshing (read, repair, Mesh_3, quality) [ms]
};

class Simulation {
public:
    /// Builds the mesh and model the scene asks for. Throws SceneError, FileError, MeshError.
    explicit Simulation(scene::Scene scene);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    const scene::Scene& scene() const;

    /// Advances one tick (static scenes: solves to equilibrium once, then holds). Never throws.
    StepReport step();
    /// Back to the state right after construction (uncut mesh, zero displacement).
    void reset();

    long tick() const;
    double time() const; ///< [s]
    bool is_static() const;

    /// Forces and grabs. Throw InputError (non-finite numbers, radius <= 0) without change.
    long add_force(const ForceSpec& f);
    bool remove_force(long id);
    long grab(const GrabSpec& g);
    bool move_grab(long id, const Vec3& target);
    bool release(long id);

    /// Rigid tools (tools.hpp): created at a pose, moved to a new pose (applied at the next
    /// step), removed. add_tool and move_tool throw InputError (non-finite or out-of-range
    /// numbers, a zero quaternion) without change; move/remove return false for an unknown id.
    long add_tool(const ToolSpec& tool);
    bool move_tool(long id, const ToolPose& pose);
    bool remove_tool(long id);
    std::size_t tool_count() const;
    /// Every tool by id, its shape with the pose it had during the last step (what a renderer
    /// draws beside the surface of that step).
    std::vector<std::pair<long, ToolSpec>> tools() const;
    /// The reaction on every tool and obstacle in the state after the last step (tools first,
    /// by id; then obstacles in scene order). Empty when the scene has neither.
    const std::vector<BodyReaction>& contact_reactions() const;
    /// Wall time of the contact work of the last step (detection and the reactions) [ms].
    double contact_ms() const;

    /// Cuts along world-space sweep triangles; never throws. The summary's status says what
    /// happened: Rejected (non-finite, absurdly distant or degenerate triangles; nothing
    /// changed), Failed (the cutter or the model could not carry it out; undone, nothing
    /// changed), Deferred (the tick's cut budget ran out; the last triangles wait) or Applied.
    /// Triangles outside the tissue or too small to cut at the tissue's scale change nothing
    /// (CutSummary::triangles_skipped). A cut whose next step() fails is undone by that step
    /// (StepReport::cut_undone).
    /// `max_triangles` > 0 also caps the triangles cut in this call (the rest is Deferred; the
    /// server's per-tick triangle budget, protocol Limits::cut_triangles_per_tick).
    CutSummary cut(const std::vector<std::array<Vec3, 3>>& world_triangles, int max_triangles = 0);
    /// Builds what cutting needs (the cut pipeline's cutter and adjacency, its grid of the uncut
    /// mesh and its undo mirror) now instead of in the first cut's tick: the server calls it
    /// where it builds a scene, off the loop. Optional; cut() builds whatever is missing.
    void prepare_cutting();
    /// How far a scalpel blade should move between the samples a client's stroke is swept
    /// from [m]: cell splitting cuts strips at least a quarter of the mean cell size wide (one
    /// sliver strip per tick from a slowly moving blade makes slivers, and costs a cut each);
    /// 0 for face snapping, which keeps crossings between ticks.
    double blade_min_advance() const;
    /// The longest move of a scalpel blade that is swept as one quad [m]: the mean cell size of
    /// the uncut mesh (0: no limit). The server sweeps a longer move between two samples in
    /// equal steps of at most this, the blade interpolated linearly, so that the tick's cut
    /// budget (`cutting.max_cells_per_tick`) can carry part of a fast stroke to the next tick
    /// instead of cutting a 2 cm quad through the organ in one tick (issue 12 item 5).
    double blade_max_advance() const;
    /// Ends the current stroke: later triangles map to rest space afresh; with face snapping,
    /// the faces it still held back are cut now. Status Failed (nothing changed) when that cut
    /// fails; like a cut, it is undone by the next step() if that step fails.
    CutSummary end_stroke();

    /// Surface in the current configuration.
    Surface surface() const;
    /// Positions only (#V x 3), for frames without a topology change.
    void surface_positions(std::vector<float>& out) const;
    std::uint64_t topology_version() const;

    /// Displacement [m] at a named probe (interpolated in the cell that contains it).
    Vec3 probe_displacement(const std::string& name) const;
    MeshStats mesh_stats() const;
    /// The embedded surface's figures (all zero without one).
    EmbeddedStats embedded_stats() const;
    /// Rest-space cut and swept areas without the rest of mesh_stats() (get_stats).
    CutAreas cut_areas() const;
    /// Kinetic, elastic and gravitational energy of the current state.
    Energy energy() const;
    /// DOFs, nonzeros and cells by kind of the current model.
    ModelStats model_stats() const;
    /// Displacements u [m] at rest-space points (#P): P1 interpolation in a tet, the cell's
    /// affine fit in other cells; inside[p] = 0 (u = 0) for a point in no cell (outside the
    /// tissue or in a cut's gap). A trade study compares runs on different meshes through
    /// these (issue 17 item 1).
    void sample_displacements(const std::vector<Vec3>& points, std::vector<Vec3>& u,
        std::vector<std::uint8_t>& inside) const;
    /// Number of cells, O(1) (mesh_stats() checks the surface and counts components, O(mesh)).
    Index cell_count() const;
    /// What meshing reported while the scene was built (meshed false if the geometry was not
    /// meshed by CGAL). Unchanged by reset() and cuts.
    const MeshingSummary& meshing_summary() const;
    /// What the scene built and what each part cost at load (build_report.hpp); lazy parts say
    /// whether they have been built since. reset() builds again and measures again.
    BuildReport build_report() const;
    /// Node world positions (#N) [m].
    const std::vector<Vec3>& positions() const;
    /// Hash of the whole dynamic state (positions, velocities, topology) for determinism tests.
    std::uint64_t state_hash() const;

    /// Writes the volume mesh at its world positions as VTU with, per node, "displacement" [m],
    /// "velocity" [m/s] (zero for static scenes) and "cut" (1 on a cut surface, else 0), and per
    /// cell "stress" (Cauchy, 9 components row-major) [Pa], "von_mises" [Pa] and "cut" (the
    /// number of the cell's faces on a cut surface).
    void write_vtu(const std::string& path) const;

private:
    friend struct SimulationTestPeer; // tests reach the undo of a failed cut through it
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::sim
