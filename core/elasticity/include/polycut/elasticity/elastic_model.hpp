// The assembled elastic model of a mesh (DESIGN.md sec. 3-4): per-cell integration data, element
// stiffness, lumped mass and fit gradients cached in rest space; a DOF numbering that eliminates
// fixed DOFs; a CSC sparsity pattern of the reduced stiffness built once per topology, with a
// scatter map from every cell matrix entry to its value slot so per-step assembly is a tight,
// allocation-free loop. Forces: f = -R Ke (R^T (x - x_c) - (X - X_c)) per cell (corotated), or
// f = -Ke (x - X) (linear); stiffness R Ke R^T (the dR/dx term is neglected, as in 000 sec. 3.6).
#pragma once

#include "polycut/basis/cell_basis.hpp"
#include "polycut/common/sparse.hpp"
#include "polycut/elasticity/material.hpp"
#include "polycut/elasticity/model.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace polycut::elasticity {

namespace detail {
class NodalDilatation;
struct StepProduct;
} // namespace detail

/// One fixed-DOF mask entry per DOF (3#N), 1 = fixed. Helper: fix all three DOFs of the nodes
/// with node_mask[i] != 0.
std::vector<std::uint8_t> fix_nodes(const std::vector<std::uint8_t>& node_mask);

/// The elastic model of a mesh. Holds a pointer to the mesh, which must outlive it; after the
/// mesh is edited (a cut), call update_cells() or rebuild_topology() before the next assembly.
class ElasticModel : public Model {
public:
    /// fixed_dofs: per-DOF mask (3#N, 1 = fixed; may be empty = nothing fixed). Throws
    /// InputError for a bad material or mask size, MeshError for an invalid cell.
    ElasticModel(const mesh::Mesh& mesh, const Material& material,
        const basis::BasisOptions& options, std::vector<std::uint8_t> fixed_dofs);
    ~ElasticModel() override;
    ElasticModel(ElasticModel&&) noexcept;
    ElasticModel& operator=(ElasticModel&&) noexcept;

    const mesh::Mesh& mesh() const { return *m_mesh; }
    const Material& material() const override { return m_material; }
    Index num_nodes() const { return Index(m_mass.size()); }
    /// Number of free DOFs = size of the reduced system.
    Index num_free_dofs() const override { return m_num_free; }
    /// Full DOF (3 node + axis) -> reduced DOF, or kNone when fixed (3#N).
    const std::vector<Index>& dof_map() const override { return m_dof_map; }
    /// Per-DOF fixed mask (3#N).
    const std::vector<std::uint8_t>& fixed_dofs() const { return m_fixed; }
    /// Lumped nodal masses (#N) [kg].
    const VecX& nodal_mass() const { return m_mass; }
    // Model: the rows are the nodes.
    Index num_rows() const override { return num_nodes(); }
    void rest_rows(MatX3& X0) const override;
    const VecX& row_mass() const override { return m_mass; }
    void add_gravity(const Vec3& g, VecX& full) const override;
    /// Lumped mass per reduced DOF (#free) [kg]: the inertia of a dynamic step. Made on the first
    /// call after a change of cells or fixed DOFs, so a static model never builds it (issue 17
    /// item 6; inertia_built()).
    const VecX& reduced_mass() const override;
    /// Whether reduced_mass() was ever asked for (a dynamic integrator's inertia).
    bool inertia_built() const { return m_inertia_built; }
    /// Cell integrations (basis functions and quadrature) computed so far, by basis, counting the
    /// recomputations after cuts: P1 for tets, Q1 for hexes, the polyhedral basis (mean value or
    /// harmonic) for other cells.
    struct BasisCounts {
        long p1 = 0;
        long q1 = 0;
        long polyhedral = 0;
    };
    const BasisCounts& bases_built() const { return m_bases_built; }
    /// Value slot in the CSC arrays of the diagonal entry of each reduced DOF (#free).
    const std::vector<Index>& diagonal_slots() const { return m_diag_slots; }
    /// Cached integration data and stiffness of a cell.
    const basis::CellIntegration& cell_integration(Index c) const {
        return m_cells[std::size_t(c)].integration;
    }
    Eigen::Map<const MatX> cell_stiffness(Index c) const;
    /// With basis::VolumetricRule::NodalAverage, an upper bound of the largest eigenvalue of
    /// M^-1 K of the nodal volumetric term at rest [1/s^2] (cell_stiffness() then holds only the
    /// deviatoric part, so an explicit step limit must add this); 0 for the other rules.
    double nodal_volumetric_omega2() const;
    /// Current rotation of a cell (identity until a corotated assembly).
    const Mat3& cell_rotation(Index c) const { return m_rotation[std::size_t(c)]; }

    /// A reduced matrix (#free x #free) with the model's sparsity pattern, all values zero.
    /// Matrices made before a topology change must be remade.
    SparseMatrix make_matrix() const override;
    /// The pattern into M's storage, reallocated (with 10 % to spare) only when it grows past
    /// it: a cut's new ~10 MB matrices were a third of the step's topology update on the cut
    /// 5k organ, mostly page faults and zero fills.
    void pattern_into(SparseMatrix& M) const override;

    /// Evaluates at world positions x (#N x 3) [m]: into K (reduced, from make_matrix(); may be
    /// null) the stiffness, and into f_int (3#N, resized; may be null) the elastic nodal forces [N]
    /// (including reactions on fixed DOFs). Corotated mode updates the cached cell rotations.
    /// No allocation once K and f_int have the right size.
    void assemble(const MatX3& x, ForceMode mode, SparseMatrix* K, VecX* f_int) override;
    /// Model::assemble_step: the cells' kernels scale their blocks and sum the scaled blocks
    /// times v as they scatter them (no pass over K). False with the nodal volumetric term.
    bool assemble_step(const MatX3& x, ForceMode mode, double scale, const VecX& diagonal,
        const MatX3& v, SparseMatrix& A, VecX& f_int, VecX& kv) override;

    /// Elastic energy [J] at x: sum over cells of 1/2 u^T Ke u with the same local displacement u
    /// as the forces (Corotated: rotations of x, warm-started from the cached ones).
    double elastic_energy(const MatX3& x, ForceMode mode) const override;

    /// Largest stretch of a cell at positions x (#N x 3) [m]: per cell, the longest distance from
    /// its first node to its other nodes, deformed over the same at rest (1 under rigid motion);
    /// 1 when no cell is stretched. Rest extents are cached with the cell data; uses threads().
    double max_cell_stretch(const MatX3& x) const override;
    /// The same per cell, squared: out[c] = (stretch of cell c)^2 at x (#cells; 1 for cells
    /// without extent, +inf for non-finite positions). Resized; uses threads().
    void cell_stretch_squared(const MatX3& x, std::vector<double>& out) const override;

    /// Gathers the free entries of a full DOF vector (3#N) into a reduced one (#free).
    void reduce(const VecX& full, VecX& reduced) const override;
    /// Scatters a reduced vector into the free entries of a full one (fixed entries untouched).
    void expand(const VecX& reduced, VecX& full) const;

    /// Recomputes the cached data of the listed cells after a cut edited them (rest positions,
    /// nodes). Cells appended to the mesh are picked up too. The sparsity pattern and scatter map
    /// are rebuilt when a cell's node list changed or cells were added/removed. With a
    /// `cell_map` (old cell id -> new id, kNone for a cell removed: a cut that merged slivers
    /// away), the surviving cells keep their data under their new ids and only the changed and
    /// the new ones are recomputed; node ids must not have changed. A cell whose data cannot be
    /// made (MeshError) is thrown before anything changes: the model stays that of the mesh
    /// before the edit (so does rebuild_topology()).
    void update_cells(const std::vector<Index>& changed, const std::vector<Index>& cell_map = {});
    /// Recomputes everything from the mesh (new nodes are free; existing DOF masks are kept).
    /// node_map: the renumbering that made the rebuild necessary (old node id -> new id, kNone
    /// for a node removed; a face snap's compaction), kept for node_map_since(); empty when
    /// unknown.
    void rebuild_topology(std::vector<Index> node_map = {});
    /// Replaces the fixed-DOF mask (3#N) and rebuilds the DOF numbering and pattern.
    void set_fixed_dofs(std::vector<std::uint8_t> fixed_dofs);

    /// The undo of cut edits without a rebuild (issue 12 item 5, issue 14 item 1; decision
    /// 0070). mark_undo() opens a mark and returns its serial, noting the cell and node counts
    /// and the fixed DOFs of the moment; while a mark is open, each update_cells() is journaled
    /// with what running it backwards needs (the data of the cells it replaced or merged away,
    /// its cell map). revert_to_mark() puts the model back as it was at that mark once the mesh
    /// is back too (CutPipeline::undo): the replaced and merged cells return, the appended ones
    /// go, the pattern is made again around their nodes only, and the node ids stay
    /// (nodes_kept_since(): a preconditioner follows by a remap). It drops that mark and the
    /// later ones. It returns false when the mark is unknown (forgotten, or dropped by a
    /// rebuild_topology() since) or the cells it comes to are not the mesh's: the caller must
    /// then call rebuild_topology(). forget_marks(): the edits are accepted.
    std::uint64_t mark_undo();
    bool revert_to_mark(std::uint64_t mark);
    /// Drops one mark that will not be reverted to, keeping the journal for the earlier marks
    /// (a cut's snapshot discarded after the cut: only the tick's first one stays restorable).
    void drop_mark(std::uint64_t mark);
    void forget_marks();
    /// Marks held (for tests).
    std::size_t undo_marks() const { return m_marks.size(); }
    /// Incremented whenever the pattern (and DOF numbering) changes.
    std::uint64_t topology_version() const override { return m_topology_version; }
    /// Whether the node ids are the same as at topology version `version` (cuts that only
    /// edited cells and appended nodes; not after rebuild_topology(), which a renumbering or an
    /// undo calls): then full DOF k means the same node and axis, and a preconditioner of then
    /// can be carried over through the old dof_map() instead of rebuilt.
    bool nodes_kept_since(std::uint64_t version) const override {
        return version >= m_renumber_base;
    }
    const std::vector<Index>* node_map_since(std::uint64_t version) const override {
        const bool once = version < m_renumber_base && version >= m_previous_renumber_base;
        return once && !m_node_map.empty() ? &m_node_map : nullptr;
    }
    /// Incremented whenever cell data (rest shape, Ke) or the fixed DOFs change (update_cells,
    /// rebuild_topology, set_fixed_dofs): a cached stiffness is stale after it moves.
    std::uint64_t cell_version() const override { return m_cell_version; }

    /// Threads for assemble() (>= 1; 1 = serial, the default). With T > 1 the nodes are split
    /// into T ranges balanced by cell count; thread t assembles, in cell order, the cells whose
    /// nodes all lie in its range (no two threads touch the same entry of K or f), then one
    /// thread the cells across ranges. Every entry thus sums its terms in an order fixed by T:
    /// results are deterministic for a given T, and T = 1 is the plain serial loop. Meshes
    /// numbered for locality (mesh::reorder_for_locality, box grids) leave few cells across
    /// ranges; after a cut, new nodes take the range of the cells that made them, so a cut's
    /// cells stay in their thread.
    void set_threads(int threads) override;
    int threads() const override { return m_threads; }
    /// Cells across the threads' node ranges (0 when serial), for reports and tests: with two
    /// threads most run in two groups after the threads' own cells, the rest serially.
    Index shared_cells() const {
        Index n = Index(m_shared_cells.size());
        for (const auto& g : m_shared_groups)
            n += Index(g.size());
        return n;
    }
    /// Of those, the cells assembled serially.
    Index serial_cells() const { return Index(m_shared_cells.size()); }
    /// Cells each thread of a threaded assembly takes, in thread order (one entry when serial).
    std::vector<Index> thread_cell_counts() const {
        std::vector<Index> counts;
        for (const auto& cells : m_thread_cells)
            counts.push_back(Index(cells.size()));
        return counts;
    }

private:
    struct CellData {
        basis::CellIntegration integration;
        std::vector<Index> nodes; ///< copy of the mesh cell's nodes when the data was built
        MatX stiffness; ///< Ke (3n x 3n)
        MatX3 fit; ///< fit gradients G (n x 3)
        MatX3 rest_local; ///< X_i - X_c (n x 3)
    };
    /// Compact data of a one-point 4-node cell (P1 tet) for the closed-form corotated kernel:
    /// blocks R Ke_ij R^T = V (lambda r_i r_j^T + mu r_j r_i^T + mu g_i.g_j I), r_i = R g_i.
    struct P1Cell {
        bool valid = false;
        Index nodes[4] = { 0, 0, 0, 0 };
        double g[4][3] = {}; ///< P1 gradients [1/m]
        double c0[3][3] = {}; ///< sum_j (X_j - X_c) g_j^T (the identity up to round-off)
        double volume = 0; ///< quadrature weight [m^3]
    };
    /// What compute_cell() makes of one cell, apart from the model.
    struct ComputedCell {
        CellData data;
        P1Cell p1;
        double extent2 = 0; ///< squared rest extent [m^2]
    };
    void compute_cell(Index c, ComputedCell& out) const;
    /// compute_cell() for each listed cell, in parallel with the model's threads; throws the
    /// first failure in list order, having changed nothing.
    std::vector<ComputedCell> compute_detached(std::span<const Index> cells) const;
    /// Puts what compute_detached() made into the listed cells' slots.
    void commit_cells(std::span<const Index> cells, std::vector<ComputedCell>&& made);
    void rebuild_mass();
    /// rebuild_mass() for the nodes marked in `affected` (#nodes) only: their masses are summed
    /// again over their cells, in the order rebuild_mass() takes, so the result is the same to
    /// the bit (checked with POLYCUT_CHECK_UNDO=1); a cut costs a pass over the flat cell-node
    /// list instead of one over every cell's data. Needs the pattern's node lists current.
    void update_mass(const std::vector<char>& affected);
    /// Rebuilds the nodal volumetric term (NodalAverage) from the cells and the pattern.
    void refresh_nodal();
    void rebuild_pattern();
    /// The pattern after a cut: `affected` (#nodes) marks the nodes whose set of cells changed
    /// (nodes appended since the last build count as affected), `old_cell` (#cells) maps each cell
    /// to its id at the last build when it is the same cell (kNone: new or changed). Only the
    /// affected nodes' columns and the cells touching them are built; the rest is copied with
    /// shifted value slots. Empty arguments, or old nodes whose DOFs would be renumbered: a full
    /// build.
    void build_pattern(std::vector<char> affected, std::vector<Index> old_cell);
    void rebuild_partition();
    /// rebuild_partition()'s last part: m_shared_groups from m_shared_cells (two threads).
    void split_shared_cells();
    /// assemble(), or assemble_step() with `step`.
    void assemble_impl(const MatX3& x, ForceMode mode, SparseMatrix* K, VecX* f_int,
        const detail::StepProduct* step);
    /// Assembles the listed cells (in order) into Kvals / fint (either may be null); with
    /// `step` (may be null) the blocks are scaled and multiplied with its velocities.
    void assemble_cells(const std::vector<Index>& cells, const MatX3& x, bool corotated,
        double* Kvals, double* fint, const detail::StepProduct* step);

    const mesh::Mesh* m_mesh;
    Material m_material;
    basis::BasisOptions m_options;
    std::vector<std::uint8_t> m_fixed;
    std::vector<CellData> m_cells;
    std::vector<Mat3> m_rotation;
    std::vector<P1Cell> m_p1; ///< per cell; valid for one-point 4-node cells
    VecX m_mass;
    mutable VecX m_reduced_mass; ///< made by reduced_mass() when m_reduced_mass_stale
    mutable bool m_reduced_mass_stale = true;
    mutable bool m_inertia_built = false;
    BasisCounts m_bases_built;
    std::vector<Index> m_dof_map;
    std::vector<Index> m_free_dofs; ///< reduced -> full
    Index m_num_free = 0;
    // Pattern: CSC of the reduced stiffness; scatter[c] has (3n)^2 value slots (kNone if fixed).
    std::vector<int> m_outer;
    std::vector<int> m_inner;
    std::vector<std::size_t> m_scatter_offset;
    std::vector<int> m_scatter;
    std::vector<Index> m_diag_slots;
    /// Topology version since which node ids are stable (see nodes_kept_since()).
    std::uint64_t m_renumber_base = 0;
    std::uint64_t m_previous_renumber_base = 0; ///< the one before m_renumber_base
    std::vector<Index> m_node_map; ///< of the renumbering at m_renumber_base (may be empty)
    // Node-level pattern: neighbours of each node (CSR, sorted), where each neighbour's rows
    // start within the node's columns, and the column length.
    std::vector<std::size_t> m_nb_offset;
    std::vector<Index> m_nb_nodes;
    std::vector<int> m_nb_start;
    std::vector<int> m_nb_length;
    /// Per cell, 20 ints: the compact scatter of a 4-node cell whose 12 DOFs are free (see
    /// detail::P1TetView::block); first entry -1 when the full scatter must be used.
    std::vector<int> m_block_scatter;
    /// The storage of the pattern's largest arrays before the last build_pattern(): the next
    /// one fills it instead of new memory (fresh pages zero-filled were ~17 % of a pattern
    /// update per cut on organ_5k).
    struct SpareArrays {
        std::vector<int> inner, scatter, block_scatter, nb_start;
        std::vector<Index> nb_nodes;
    } m_spare;
    std::uint64_t m_topology_version = 0;
    std::uint64_t m_cell_version = 0;
    int m_threads = 1;
    /// Threaded assembly: cells per thread (all nodes in its range), then the rest (serial).
    std::vector<std::vector<Index>> m_thread_cells;
    std::vector<Index> m_shared_cells;
    /// Two threads: the shared cells on either side of a split of their band of nodes, each
    /// group assembled by one thread after the threads' own cells (empty: all are serial).
    std::vector<std::vector<Index>> m_shared_groups;
    /// Nodes the assembly's node ranges were made on (later nodes, appended by cuts, take the
    /// range of their cells); 0 until the first partition or after a renumbering.
    Index m_partition_nodes = 0;
    /// Flat copies for the stretch check (cache-friendly): cell nodes (CSR by cell, rebuilt
    /// with the pattern) and max_k |X_k - X_0|^2 per cell [m^2] (with the cell data).
    std::vector<std::size_t> m_node_offset;
    std::vector<Index> m_node_list;
    std::vector<double> m_rest_extent2;
    /// The volumetric term of VolumetricRule::NodalAverage (null otherwise); its patches widen
    /// the pattern to two rings (nodal_dilatation.hpp).
    std::unique_ptr<detail::NodalDilatation> m_nodal;
    /// The undo journal (mark_undo()): one entry per update_cells() since the oldest mark, with
    /// what it needs to be run backwards: the cell count before it, its cell map, and the data
    /// of the cells it replaced (by id after its cell map) and of those it merged away (old id).
    struct SavedCell {
        Index cell = kNone;
        ComputedCell data;
    };
    struct JournalEntry {
        std::size_t cells_before = 0;
        std::vector<Index> cell_map;
        std::vector<SavedCell> removed;
        std::vector<SavedCell> replaced;
    };
    /// Per mark: the counts and fixed DOFs then and the journal entries after it.
    struct UndoMark {
        std::uint64_t serial = 0;
        std::size_t cells = 0;
        std::size_t nodes = 0;
        std::vector<std::uint8_t> fixed;
        std::size_t entry_begin = 0;
    };
    std::vector<UndoMark> m_marks;
    std::vector<JournalEntry> m_journal;
    std::uint64_t m_next_mark = 1;
    /// Cell c's data, copied (or moved) out for the journal.
    SavedCell save_cell(std::size_t c, bool move);
    /// POLYCUT_CHECK_UNDO=1: the pattern revert_to_mark() made equals a full build (throws).
    void check_pattern_against_rebuild();
};

} // namespace polycut::elasticity
