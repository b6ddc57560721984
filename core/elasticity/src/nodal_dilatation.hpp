// Averaged nodal dilatation (basis::VolumetricRule::NodalAverage, docs/decisions/0050): the
// volumetric part of the strain energy is evaluated per node from the volume-weighted mean of the
// cell dilatations around the node (the averaged nodal pressure tet of Bonet & Burton 1998; the
// volumetric half of Dohrmann et al. 2000's node-based uniform strain), while the cells keep only
// their deviatoric stiffness. One pressure per node instead of one per cell: P1 tets stop locking
// near nu = 0.5. Works on any cell (tets, hexes, cut polyhedra) through its CellIntegration.
//
//   theta_e = sum_k d_ek . (R_e^T x_k) - c_e          (cell dilatation, corotated; = tr(R^T F) - 3)
//   theta_a = sum_{e ∋ a} (V_ae / V_a) theta_e         (node a; V_ae the lumped volume of a in e)
//   E_vol   = sum_a (kappa / 2) V_a theta_a^2          (kappa the bulk modulus)
//
// with d_ek the cell's mean divergence row of node k [1/m] (its mean zero, so theta_e is blind
// to translations) and c_e = sum_k d_ek . X_k. Forces -dE/dx with R held fixed, stiffness
// sum_a kappa V_a beta_a beta_a^T, beta_a = d theta_a / dx, as the cells drop dR/dx. beta_a spans
// the nodes of the cells around a, so K couples nodes two rings apart: ElasticModel widens its
// pattern (elastic_pattern.cpp) when the rule is on. Internal to polycut_elasticity.
#pragma once

#include "polycut/basis/cell_integration.hpp"
#include "polycut/common/types.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

namespace polycut::elasticity::detail {

/// What NodalDilatation reads of one cell of the model.
struct NodalCellView {
    const std::vector<Index>* nodes; ///< the cell's node ids
    const basis::CellIntegration* integration; ///< gradients, weights, lumped volumes
    const MatX3* rest_local; ///< X_k - X_c (n x 3) [m]
};

/// Views into ElasticModel's CSC pattern (see elastic_pattern.cpp): the rows of the columns of
/// node j are the free DOFs of its neighbours (sorted), neighbour i's rows starting at
/// nb_start[q] where nb_nodes[q] = i, q in [nb_offset[j], nb_offset[j + 1]); every column of
/// node j has nb_length[j] rows.
struct PatternView {
    std::span<const int> outer; ///< column starts (#free + 1)
    std::span<const std::size_t> nb_offset; ///< (#N + 1)
    std::span<const Index> nb_nodes;
    std::span<const int> nb_start;
    std::span<const int> nb_length; ///< (#N)
    std::span<const Index> dof_map; ///< full DOF -> reduced DOF or kNone (3#N)
};

/// The nodal volumetric term of a model. Rebuilt whenever the cells, fixed DOFs or pattern change.
class NodalDilatation {
public:
    /// Rebuilds the per-cell and per-node data and the scatter of the patch matrices into the
    /// pattern, which must already couple every two nodes of one patch. kappa: bulk modulus [Pa].
    /// Throws StateError when a patch pair is missing from the pattern.
    void rebuild(Index num_nodes, Index num_cells, const std::function<NodalCellView(Index)>& cell,
        double kappa, const PatternView& pattern);

    /// Adds forces (3#N, reactions included) [N] and stiffness values (the pattern's slots) of the
    /// volumetric term at positions x (#N x 3) [m]; either output may be null. rotations: per cell
    /// R_e (#cells), used when corotated (identity otherwise).
    void assemble(const MatX3& x, std::span<const Mat3> rotations, bool corotated, double* Kvals,
        double* fint);

    /// Volumetric energy [J] at x with the cell rotations (identity when !corotated).
    double energy(const MatX3& x, std::span<const Mat3> rotations, bool corotated) const;

    /// An upper bound of the largest eigenvalue of M^-1 K_vol at rest [1/s^2] (each node patch
    /// a rank-one matrix: kappa V_a beta_a^T M^-1 beta_a, the largest over patches times the most
    /// patches sharing a node, Irons-style) with the lumped nodal masses (#N) [kg].
    double omega2_bound(const VecX& nodal_mass) const;

    /// Nonzero value slots the patch scatter holds (for reports).
    std::size_t scatter_size() const { return m_pair_slot.size(); }

private:
    /// Per cell: the dilatation theta_e at x and the rotated divergence rows R d_ek into m_rd.
    void cell_dilatations(
        const MatX3& x, std::span<const Mat3> rotations, bool corotated, bool rows) const;
    /// theta_a from the cell dilatations of the last cell_dilatations() (0 for unused nodes).
    double node_dilatation(std::size_t a) const;
    /// beta_a = sum_{e ∋ a} (V_ae / V_a) rows_ek over the patch of a (3m), rows_ek being R_e d_ek
    /// (m_rd) or d_ek (m_div, at rest).
    void patch_gradient(
        std::size_t a, const std::vector<Vec3>& rows, std::vector<double>& beta) const;

    double m_kappa = 0;
    // Cells (CSR over cell nodes): node ids, divergence rows d_ek [1/m], lumped volumes V_ek
    // [m^3], and c_e.
    std::vector<std::size_t> m_cell_offset;
    std::vector<Index> m_cell_nodes;
    std::vector<Vec3> m_div;
    std::vector<double> m_lumped;
    std::vector<double> m_c;
    // Nodes: V_a [m^3]; the patch (sorted nodes of the cells around a) as CSR; the incidences
    // (a in cell e at local k) as CSR by node, each with the patch positions of e's nodes.
    std::vector<double> m_node_volume;
    std::vector<std::size_t> m_patch_offset;
    std::vector<Index> m_patch_nodes;
    std::vector<std::size_t> m_inc_offset;
    std::vector<Index> m_inc_cell;
    std::vector<int> m_inc_local;
    std::vector<std::size_t> m_inc_pos_offset;
    std::vector<int> m_inc_pos;
    // Scatter: per patch, m x m base slots (row p, column q; -1 when either node has no free
    // DOF); entry (3p + a, 3q + b) is at base + rank_q(b) L_q + rank_p(a). Per node: the rank of
    // each axis among its free ones (-1 fixed) and its column length L.
    std::vector<std::size_t> m_pair_offset;
    std::vector<int> m_pair_slot;
    std::vector<std::array<signed char, 3>> m_rank;
    std::vector<int> m_length;
    // Scratch for assemble()/energy().
    mutable std::vector<double> m_theta_cell;
    mutable std::vector<Vec3> m_rd;
    std::vector<double> m_theta_node;
    std::vector<double> m_beta;
};

} // namespace polycut::elasticity::detail
