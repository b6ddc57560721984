// Private state of sim::Simulation, shared by its source files.
#pragma once

#include "dg_part.hpp"
#include "polycut/cut/pipeline.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/integrate/options.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/sim/simulation.hpp"
#include "polycut/surface/extract.hpp"

#include <map>
#include <memory>

namespace polycut::contact {
class ContactField; // contact.cpp and simulation.cpp see it whole
struct Samples;
} // namespace polycut::contact
namespace polycut::contact {
class TriangleMeshDistance; // embedded.cpp
}
namespace polycut::embed {
struct Embedding; // embedded.cpp
struct SplitState;
struct CutChange;
} // namespace polycut::embed
namespace polycut::meshing {
class Octree; // octree_refine.cpp and simulation.cpp see it whole
}

namespace polycut::sim {

/// Nodes and weights a force or grab acts on (material points, fixed at creation).
struct NodeWeights {
    std::vector<Index> nodes;
    std::vector<double> weights; ///< sum to 1
};

struct ActiveForce {
    ForceSpec spec;
    NodeWeights at;
    double expires = 0; ///< sim time [s]; <= 0: never
};

/// A grab: each grabbed node hangs on a zero-length spring of stiffness `spec.stiffness * w`
/// whose anchor is `target` plus the node's offset from the weighted centroid at grab time. The
/// total force is the centroid spring's, k (target - x_c); holding the offsets keeps the grabbed
/// patch in its shape instead of pulling it into one point. Per-node springs have a diagonal
/// stiffness, so the integrator treats them implicitly (integrate/springs.hpp).
struct ActiveGrab {
    GrabSpec spec;
    NodeWeights at;
    Vec3 target = Vec3::Zero(); ///< [m]
    /// Offsets x_k - x_c at grab time [m], each with its node's rest position: a cut renumbers
    /// `at.nodes` (and may split a node in two, both at the same rest point), so a node finds
    /// its offset by rest position.
    std::vector<Vec3> offset_rest, offset;
    std::vector<Index> offset_nodes; ///< `at.nodes` the cached `node_offset` belongs to
    std::vector<Vec3> node_offset; ///< offset per entry of `at.nodes`
};

struct Simulation::Impl {
    scene::Scene scene;
    MeshingSummary meshing; ///< what CGAL meshing reported while building initial_mesh
    /// The parts build() made, with their cost (build_report.cpp); [0] is the mesh
    std::vector<BuildPart> build_parts;
    mesh::Mesh initial_mesh; ///< for reset()
    mesh::Mesh mesh;
    std::vector<std::uint8_t> node_fixed_mask; ///< per DOF (3#N), from the scene's fixed sets
    std::unique_ptr<elasticity::ElasticModel> model; ///< null for method dg
    /// Method dg: the DG model (the integrator's), stitching and loads; null otherwise.
    std::unique_ptr<DgPart> dg;
    std::unique_ptr<integrate::Integrator> integrator;
    /// World sweep triangles to cuts (core/cut's one pipeline; made on the first cut).
    std::unique_ptr<cut::CutPipeline> cutting;
    /// Makes `cutting` for the current mesh if there is none.
    void ensure_cutting();
    /// Simulation::blade_min_advance(): samples of a splitting stroke closer than this [m] are
    /// swept together (the server holds scalpel samples, the pipeline coarsens cut strips).
    double blade_min_advance() const;
    /// Throws when the cut mesh's element matrices outgrew cutting.max_model_growth (the
    /// caller undoes the cut; the model has not followed it yet).
    void check_model_growth() const;
    /// prepare_cutting() built `cutting` at load (its cost is the "cut" entry of build_parts)
    bool cutting_prepared = false;
    /// Cells the cuts of this tick may still change (scene cutting.max_cells_per_tick; reset
    /// by step()); the triangles past it are deferred to the next tick.
    Index cut_cells_left = 0;
    /// The state a cut may change, kept so a failed cut can be undone. The mesh is not in it:
    /// the cut pipeline keeps the mesh before its last call (CutPipeline::undo).
    struct Snapshot {
        integrate::State state;
        std::vector<std::uint8_t> node_fixed_mask;
        VecX scene_forces;
        std::map<long, ActiveForce> forces;
        std::map<long, ActiveGrab> grabs;
        double swept_area = 0;
        surface::Topology topology;
        std::uint64_t topology_version = 0;
        /// The model's undo mark (ElasticModel::mark_undo) of the moment; 0: none (DG).
        std::uint64_t model_mark = 0;
    };
    /// The state a cut may change, copied into the buffers of a snapshot no longer needed
    /// (`spare`), so the copy writes into memory already mapped.
    std::unique_ptr<Snapshot> take_snapshot();
    /// A snapshot that will not be restored: its model mark is dropped and its buffers kept as
    /// `spare`.
    void discard(std::unique_ptr<Snapshot> snap);
    std::unique_ptr<Snapshot> spare;
    /// The state before the first cut since the last step: kept until that step has shown the
    /// cut mesh is mechanically sound; a step that fails right after a cut undoes the cut too.
    std::unique_ptr<Snapshot> cut_undo;
    /// Puts the mesh (CutPipeline::undo), state and model back as they were: the model from its
    /// undo journal (the cells the cuts replaced, decision 0070), rebuilt only when the journal
    /// cannot follow (a renumbering since). The
    /// surface topology and its version come back too when nothing was published since the snapshot
    /// (`published` false: a failed cut changes nothing a client can see); otherwise the old
    /// topology gets a new version, so clients that saw the cut fetch it again.
    void restore(const Snapshot& snap, bool published = false);
    /// Static scenes: fixes every connected piece without a fixed DOF at one boundary face;
    /// returns how many pieces it fixed.
    int fix_free_pieces();
    /// Dynamic scenes: fragments (at most 64 cells and 1 % of the body's volume) that a cut
    /// freed from every fixed node, reached from `changed`, are held where they are (their
    /// nodes fixed). Returns how many.
    int pin_free_fragments(const std::vector<Index>& changed);
    integrate::State state;
    VecX scene_forces; ///< (3#N) constant nodal loads from the scene [N]
    VecX f_ext; ///< (3#N) work vector [N]
    std::map<long, ActiveForce> forces;
    std::map<long, ActiveGrab> grabs;
    long next_id = 1;
    long tick = 0;
    double time = 0;
    bool static_solved = false; ///< static scenes: loads unchanged since the last solve
    surface::Topology topology;
    std::uint64_t topology_version = 1;
    double swept_area = 0; ///< rest area swept inside the uncut tissue by applied cuts [m^2]
    /// Most inverted tets around one cut call since the last step (its report warns).
    std::size_t cut_inverted = 0;
    /// Sweep triangles skipped since the last step as mapped through a fold (CutResult::stretched).
    std::size_t cut_stretched = 0;
    /// Rest area swept by cuts that were undone: failed cuts and those a failed step took back
    /// [m^2]. Not restored by an undo: the blade swept it.
    double swept_area_undone = 0;
    /// Cube root of the uncut mesh's mean cell volume [m]: the length the cut tolerances and the
    /// blade's minimum advance are relative to.
    double initial_cell_size = 0;
    /// Entries of the uncut mesh's element matrices, sum of (3 nodes)^2 over the cells
    /// (cutting.max_model_growth)
    double initial_element_cost = 0;
    double body_volume = 0; ///< rest volume of the scene as built [m^3]
    /// Largest rest bounding-box diagonal of a cell of the uncut mesh [m]: how far a material
    /// point can be from its nearest node (pick()).
    double max_cell_diameter = 0;
    std::vector<Vec3> positions; ///< world positions (#N) [m], mirror of state.x

    // Contact (contact.cpp): the penalty field with the scene's obstacles and the tools,
    // made when the scene has obstacles or the first tool arrives.
    std::unique_ptr<contact::ContactField> contact;
    struct Tool {
        ToolSpec spec;
        long body = 0; ///< id in `contact`
        ToolPose pose; ///< where the client put it (applied at the next step)
        ToolPose stepped; ///< where it was during the last step
    };
    std::map<long, Tool> tools;
    std::vector<long> obstacle_bodies; ///< body id of each scene obstacle
    std::vector<long> scripted_tools; ///< tool id of each scene tool (scene.tools)
    std::uint64_t contact_samples_version = 0; ///< topology_version the samples were made at
    std::vector<BodyReaction> reactions;
    double contact_ms = 0;
    /// Makes the contact field (once) and hands it to the integrator.
    contact::ContactField& ensure_contact();
    /// build(): the scene's obstacles (when it has any).
    void build_obstacles();
    // Embedded surface (embedded.cpp): the scene's detailed surface in the current mesh, and
    // the cut lips of the mesh streamed with it.
    std::unique_ptr<embed::Embedding> embedded;
    std::vector<std::array<Index, 3>> embedded_triangles; ///< of the surface file
    std::size_t embedded_loaded_vertices = 0; ///< its vertices: the first of `embedded->rest`
    std::uint64_t embedded_version = 0; ///< topology_version the embedding belongs to
    std::vector<Index> lip_vertex_nodes; ///< mesh node of each lip vertex
    std::vector<std::uint32_t> lip_triangles; ///< (#T x 3) into the lip vertices
    double embed_ms = 0; ///< wall time of the last (re-)embedding [ms]
    /// Splitting the surface along the cuts (embed/split.hpp): what it keeps between cuts, the
    /// loaded surface's inside test (rest space, made at the first cut), the cut being applied
    /// (set by note_embedding_cut() for the refresh that follows it in the same call) and the
    /// figures of the last split.
    std::unique_ptr<embed::SplitState> embedded_split;
    /// The surface as loaded, unsplit, embedded in the current mesh (each vertex in the cell
    /// that contains it), kept current cut by cut where the cut changed cells: the start of a
    /// split anew, instead of embedding every vertex again.
    std::unique_ptr<embed::Embedding> embedded_base;
    std::unique_ptr<contact::TriangleMeshDistance> embedded_inside;
    const cut::CutReport* embedded_pending_cut = nullptr;
    EmbeddedStats embedded_stats;
    /// cut.cpp, after the mesh changed and before refresh_topology(): the report, so that the
    /// embedded surface is split and re-embedded where this cut changed the mesh only.
    void note_embedding_cut(const cut::CutReport& report);
    /// Splits the embedding along the cut faces of `change` (all the mesh's Cut faces when
    /// embedding anew); false if CGAL failed (the caller then embeds the surface unsplit, and
    /// EmbeddedStats::split says so) or the cut ran over skin an earlier cut split (the caller
    /// then embeds anew and splits along all the Cut faces at once).
    bool split_embedded(const embed::CutChange& change);
    /// build(): reads and embeds the scene's surface (when it names one).
    void build_embedded();
    /// Embeds the surface in the current mesh again after a topology change (a cut); the lips
    /// come from the mesh's Cut faces.
    void refresh_embedded();
    /// Whether the embedded surface describes the current topology.
    bool embedded_current() const;
    /// The embedded surface (tag 1) plus the lips (tag 2).
    void embedded_surface(Surface& out) const;
    void embedded_positions(std::vector<float>& out) const;
    /// Contact samples of the embedded surface and the lips.
    contact::Samples embedded_samples() const;
    /// After build(): the scene's scripted tools, through `owner`'s add_tool.
    void build_scripted_tools(Simulation& owner);
    /// Before a step of length dt: samples up to date with the topology, tools at their new
    /// poses with the velocity of their motion since the last step.
    void prepare_contact(double dt);
    /// After a step: the reactions of the new state.
    void measure_contact();

    // Octree geometry with stress-based refinement (octree_refine.cpp, 001 sec. 8).
    std::unique_ptr<meshing::Octree> octree; ///< the tree whose leaves are `mesh`'s cells
    std::uint64_t octree_version = 0; ///< topology_version of the mesh the tree built
    /// build(): the scene's octree when its geometry refines (octree.refine_stress > 0).
    void build_octree();
    /// After a step: splits the cells over the stress threshold 1-to-8, builds the mesh again
    /// and carries the state over; returns how many cells it split (0: nothing changed) and
    /// puts that and the energies around the transfer in `report`. Stops for good once a cut
    /// changed the mesh.
    int refine_octree(StepReport& report);
    /// Simulation::energy() of the current state.
    Energy energy() const;

    void build();
    void rebuild_physics();
    void sync_positions();
    void refresh_topology();
    NodeWeights pick(const Vec3& world_point, double radius) const;
    void assemble_external(double sim_time);
    /// The grabs as per-node springs for the integrator.
    std::vector<integrate::NodeSpring> grab_springs();
    void fix_dofs_from_scene();
    void resize_state_after_cut(const cut::CutReport& report);
    /// The state updates after a pipeline call that changed the mesh (or the undo of a failed
    /// one); fills the summary's status. `before` is the snapshot taken before the change.
    void settle_cut(cut::CutResult& result, CutSummary& summary, Snapshot& before);
    /// Throws polycut::Error when a cell the cut changed has a non-positive or non-finite rest
    /// volume.
    void check_cut_cells(const std::vector<Index>& cells) const;
};

} // namespace polycut::sim
