// The DG elasticity model of a polyhedral mesh (seed 003, docs/decisions/0020): per-cell
// orthonormal polynomial bases, exact volume and face integrals, the IP or BZ face terms with a
// scale-invariant penalty, weak (Nitsche) Dirichlet conditions on fixed boundary faces, the
// (diagonal) consistent mass, loads, corotated forces and stiffness (003 sec. 7), and the
// displacement field evaluated anywhere.
//
// DOFs: one coefficient row (3 values) per basis function per cell, cell c owning rows
// offset(c) .. offset(c) + nb - 1; a "generalised position" vector x (#coeffs x 3, like the
// nodal positions of the CG models) holds X0 + U, X0 the rest coefficients (the identity map),
// so rigid motions and the corotated formulation read as in 003 sec. 7.
#pragma once

#include "polycut/common/sparse.hpp"
#include "polycut/dg/cell_basis.hpp"
#include "polycut/dg/face_integrals.hpp"
#include "polycut/dg/options.hpp"
#include "polycut/elasticity/material.hpp"
#include "polycut/elasticity/model.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace polycut::dg {

/// How forces and stiffness are evaluated.
enum class Warp {
    Linear, ///< small-strain DG elasticity, K constant
    Corotated, ///< 003 sec. 7: per-cell rotations, face terms split by the side whose strain
               ///< they carry, penalty unrotated
};

/// The DG model. Holds a pointer to the mesh, which must outlive it. As an elasticity::Model
/// (what the integrator steps, docs/decisions/0021) its rows are the coefficient rows, all free
/// (Dirichlet conditions are weak), with a fixed sparsity pattern: cell blocks coupled through
/// shared faces.
class DgModel : public elasticity::Model {
public:
    /// dirichlet_axes (empty, or one per dirichlet face): bit a set = component a fixed (7 =
    /// all, the default); a face listed twice fixes the union. A partial face constrains only
    /// its components, P u = 0 with P the diagonal projection (the Nitsche terms and the
    /// penalty act on P [[u]] and P sigma n; the other components are traction free).
    /// dirichlet_faces: boundary faces with u = 0 imposed weakly (Nitsche with the same flux and
    /// penalty as interior faces; BZ: penalty only). Throws InputError for bad options or
    /// material, MeshError naming a cell whose basis cannot be built.
    DgModel(const mesh::Mesh& mesh, const elasticity::Material& material, const DgOptions& options,
        std::vector<Index> dirichlet_faces = {}, std::vector<std::uint8_t> dirichlet_axes = {});
    /// The model of `mesh` after an edit (a cut) of the mesh `old` was built on, re-integrating
    /// only what the edit touched (003 sec. 10, issue 13 item 6): cell c with unchanged[c] != 0
    /// takes the basis and volume matrix of old cell source[c], and a face whose cells both
    /// carry over (a Dirichlet face: whose cell does) takes the old face's integrals; the
    /// rest is integrated afresh, then the operator is assembled. Equal to
    /// DgModel(mesh, old's material and options, dirichlet_faces, dirichlet_axes) when the
    /// flags are right (cells flagged unchanged have the old cell's geometry and node order).
    DgModel(const DgModel& old, const mesh::Mesh& mesh, const std::vector<Index>& source,
        const std::vector<std::uint8_t>& unchanged, std::vector<Index> dirichlet_faces,
        std::vector<std::uint8_t> dirichlet_axes);

    const mesh::Mesh& mesh() const { return *m_mesh; }
    const elasticity::Material& material() const override { return m_material; }
    const DgOptions& options() const { return m_options; }
    Index num_cells() const { return Index(m_bases.size()); }
    /// Number of coefficient rows (#coeffs); DOFs = 3 #coeffs.
    Index num_coefficients() const { return m_num_coeffs; }
    Index offset(Index cell) const { return m_offset[std::size_t(cell)]; }
    const CellBasis& basis(Index cell) const { return m_bases[std::size_t(cell)]; }
    /// Face penalty eta_F / (modulus) [1/m] of global face f (0 for faces without terms).
    double face_penalty(Index f) const;
    const std::vector<Index>& dirichlet_faces() const { return m_dirichlet; }
    /// Cells whose basis and volume matrix, and faces (interior and Dirichlet) whose integrals
    /// this model computed itself rather than carried over (all of them unless built by the
    /// update constructor).
    Index cells_integrated() const { return m_cells_integrated; }
    Index faces_integrated() const { return m_faces_integrated; }

    /// Rest coefficients X0 (#coeffs x 3) [m]: the identity map on every cell.
    const MatX3& rest() const { return m_rest; }
    /// Mass per coefficient row (#coeffs) [kg]: rho |K| for every row of cell K (the consistent
    /// mass is diagonal in the orthonormal basis).
    const VecX& mass() const { return m_mass; }

    /// Stiffness (3#coeffs square, symmetric, full storage) [N/m] of the linear model.
    SparseMatrix stiffness() const;
    /// Elastic forces (3#coeffs) at generalised positions x and, when K is not null, the
    /// stiffness there (Corotated: sum R K R^T, dR/dx neglected; same pattern as stiffness()).
    /// Corotated mode updates the cached cell rotations.
    void assemble(const MatX3& x, Warp warp, SparseMatrix* K, VecX* f_int);
    /// elasticity::Model::assemble_in_turns: each cell's terms in K carry the rotation they
    /// were last scattered with; a turn scatters the difference of its cells' warped blocks.
    bool assemble_in_turns(
        const MatX3& x, SparseMatrix& K, VecX& f_int, int phase, int period) override;
    /// Rotation of a cell from the last corotated assembly (identity before).
    const Mat3& rotation(Index cell) const { return m_rotation[std::size_t(cell)]; }
    /// Rotation of the affine part of cell c's map at x (polar decomposition, 003 sec. 7).
    Mat3 fit_rotation(const MatX3& x, Index cell, const Mat3& guess) const;

    /// Load (3#coeffs) [N] of a uniform body force density b [N/m^3] (gravity: rho g).
    VecX body_load(const Vec3& b) const;
    /// Load of a uniform traction t [Pa] on the listed boundary faces.
    VecX traction_load(const std::vector<Index>& faces, const Vec3& t) const;
    /// Load of a polynomial body force density: components[a] are coefficients of degree
    /// `degree` in global coordinates x [N/m^3] (manufactured solutions).
    VecX polynomial_body_load(const std::array<VecX, 3>& components, int degree) const;
    /// Right-hand side of the weak Dirichlet condition u = g0 + G x on the Dirichlet faces
    /// (zero for the default g = 0).
    VecX dirichlet_load(const Vec3& g0, const Mat3& G) const;

    // elasticity::Model (docs/decisions/0021)
    Index num_rows() const override { return m_num_coeffs; }
    void rest_rows(MatX3& X0) const override { X0 = m_rest; }
    const VecX& row_mass() const override { return m_mass; }
    /// Gravity acts on row 0 of each cell only: int_K rho g phi_i = rho g |K| delta_i0.
    void add_gravity(const Vec3& g, VecX& full) const override;
    Index num_free_dofs() const override { return 3 * m_num_coeffs; }
    const std::vector<Index>& dof_map() const override { return m_dof_map; }
    const VecX& reduced_mass() const override { return m_reduced_mass; }
    void reduce(const VecX& full, VecX& reduced) const override { reduced = full; }
    SparseMatrix make_matrix() const override { return m_pattern; }
    void assemble(
        const MatX3& x, elasticity::ForceMode mode, SparseMatrix* K, VecX* f_int) override {
        assemble(
            x, mode == elasticity::ForceMode::Corotated ? Warp::Corotated : Warp::Linear, K, f_int);
    }
    /// 1/2 u^T K u (Linear) or the sum over the corotated terms of 1/2 u_R^T K_term u_R with
    /// rotations fitted at x (warm-started from the cached ones) [J].
    double elastic_energy(const MatX3& x, elasticity::ForceMode mode) const override;
    /// Squared largest singular value of each cell's affine part F (rows 1-3).
    void cell_stretch_squared(const MatX3& x, std::vector<double>& out) const override;
    double max_cell_stretch(const MatX3& x) const override;
    std::uint64_t topology_version() const override { return 0; }
    bool nodes_kept_since(std::uint64_t) const override { return true; }
    std::uint64_t cell_version() const override { return 0; }
    void set_threads(int) override { }
    int threads() const override { return 1; }
    bool rows_are_points() const override { return false; }
    /// One block per cell: its 3 nb coefficient DOFs.
    std::vector<long> dof_blocks() const override;
    /// The continuous P1 field on the mesh's nodes (3 columns per node some cell uses), carried
    /// to each cell as the least-squares affine fit of its nodal values (coarse_space.cpp): the
    /// coarse level of the two-level preconditioner (docs/decisions/0024).
    SparseMatrix coarse_space() const override;

    /// Displacement u at rest point X in cell c from generalised positions x [m].
    Vec3 displacement(const MatX3& x, Index cell, const Vec3& X) const;
    /// Displacement gradient du/dX there.
    Mat3 displacement_gradient(const MatX3& x, Index cell, const Vec3& X) const;

private:
    struct FaceData {
        Index face = kNone;
        Index cells[2] = { kNone, kNone };
        /// The face's planar parts (one, or the triangles of a warped face)
        std::vector<FaceIntegrals> parts;
        int sides = 2; ///< 1 for a Dirichlet face
        double area = 0; ///< |F| [m^2]
        double eta = 0; ///< alpha p^2 |F| / min |K| [1/m]
        Vec3 axes = Vec3::Ones(); ///< Dirichlet faces: 1 for a fixed component, else 0
        Index node_count = 0; ///< nodes of the face's loop
    };
    /// The constructors' work; reuse[c]: old id of a cell whose integrals `old` carries.
    void build(const DgModel* old, const std::vector<Index>& reuse,
        const std::vector<std::uint8_t>& dirichlet_axes);
    /// Face block (s, t) of the consistency term A^{st} (3nb_s x 3nb_t) (see the .cpp).
    MatX consistency_block(const FaceData& fd, int s, int t) const;
    MatX penalty_block(const FaceData& fd, int s, int t) const;
    MatX penalty_part(const FaceData& fd, const FaceIntegrals& part, int s, int t) const;
    MatX volume_stiffness(const CellBasis& b) const;
    /// Builds the pattern, the constant penalty matrix, the per-cell corotated blocks and the
    /// linear stiffness (dg_assembly.cpp).
    void build_operator();
    /// Value slot of entry (row dof i, column dof j) in m_pattern.
    int slot(Index i, Index j) const;

    /// The part of the operator carried by cell c's strain, warped with R_c (003 sec. 7): the
    /// diagonal block (volume term plus the consistency terms of c's faces on c) and, per face
    /// neighbour d, the block coupling d's rows to c's columns (its transpose is the (c, d)
    /// block). Slots index m_pattern's values, column-major over each block.
    struct CellTerms {
        MatX diagonal; ///< 3nb_c x 3nb_c
        std::vector<int> diagonal_slots;
        std::vector<Index> neighbours;
        std::vector<MatX> off; ///< per neighbour d: 3nb_d x 3nb_c
        std::vector<std::vector<int>> off_slots, off_slots_t; ///< (d, c) and (c, d) entries
    };
    std::vector<CellTerms> m_terms;
    SparseMatrix m_pattern; ///< zero values
    SparseMatrix m_penalty; ///< the unrotated penalty terms, pattern of m_pattern
    SparseMatrix m_linear; ///< the linear stiffness, pattern of m_pattern
    std::vector<Index> m_dof_map; ///< identity
    VecX m_reduced_mass; ///< mass per DOF

    const mesh::Mesh* m_mesh;
    elasticity::Material m_material;
    DgOptions m_options;
    std::vector<Index> m_dirichlet;
    std::vector<CellBasis> m_bases;
    std::vector<Index> m_offset;
    Index m_num_coeffs = 0;
    std::vector<MatX> m_volume_K; ///< per cell (3nb x 3nb)
    std::vector<FaceData> m_faces; ///< faces with terms: interior and Dirichlet
    std::vector<double> m_face_eta; ///< per global face
    MatX3 m_rest;
    VecX m_mass;
    std::vector<Mat3> m_rotation;
    /// Per cell, the rotation its terms in the caller's K were warped with (assemble_in_turns);
    /// empty until a full assembly of K.
    std::vector<Mat3> m_k_rotation;
    /// Adds cell c's elastic forces at x (its warped volume and face-consistency terms, with
    /// m_rotation) to f_int.
    void add_cell_forces(const MatX3& x, Index c, VecX& f_int) const;
    mutable VecX m_uc, m_ud, m_fc, m_fd; ///< scratch of add_cell_forces()
    Index m_cells_integrated = 0, m_faces_integrated = 0;
};

/// DOF index of coefficient row k, axis a.
inline Index dof(Index row, int axis) {
    return 3 * row + axis;
}

} // namespace polycut::dg
