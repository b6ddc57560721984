// The interface the integrator steps (docs/decisions/0021): a model whose state is a set of rows
// of 3 "generalised positions" (mesh nodes for the continuous methods, ElasticModel; polynomial
// coefficients per cell for DG, dg::DgModel), with a diagonal mass per row, a reduced DOF
// numbering, a fixed sparsity pattern and corotated forces and stiffness.
#pragma once

#include "polycut/common/sparse.hpp"
#include "polycut/common/types.hpp"
#include "polycut/elasticity/material.hpp"

#include <cstdint>
#include <vector>

namespace polycut::elasticity {

/// What integrate::Integrator needs of a model. Rows: the state x is (#rows x 3) [m]; full DOF
/// vectors are 3#rows long (row-major: 3 row + axis).
class Model {
public:
    virtual ~Model() = default;

    virtual const Material& material() const = 0;
    /// Rows of the state (#rows).
    virtual Index num_rows() const = 0;
    /// The rest state X0 (#rows x 3) [m], resized.
    virtual void rest_rows(MatX3& X0) const = 0;
    /// Diagonal mass per row (#rows) [kg] (0 for rows no cell uses).
    virtual const VecX& row_mass() const = 0;
    /// Adds the load of a uniform acceleration g [m/s^2] (gravity) to a full vector (3#rows).
    virtual void add_gravity(const Vec3& g, VecX& full) const = 0;

    /// Number of free DOFs = size of the reduced system.
    virtual Index num_free_dofs() const = 0;
    /// Full DOF -> reduced DOF, or kNone when fixed (3#rows).
    virtual const std::vector<Index>& dof_map() const = 0;
    /// Mass per reduced DOF (#free) [kg].
    virtual const VecX& reduced_mass() const = 0;
    /// Gathers the free entries of a full DOF vector (3#rows) into a reduced one (#free).
    virtual void reduce(const VecX& full, VecX& reduced) const = 0;

    /// A reduced matrix (#free x #free, symmetric, full storage, every diagonal entry stored)
    /// with the model's sparsity pattern, all values zero.
    virtual SparseMatrix make_matrix() const = 0;
    /// M takes the model's sparsity pattern (as make_matrix()), in its own storage where that
    /// is large enough; its values are left unspecified (every user writes them all before
    /// reading: assemble() zeroes K, solve::scale_shift_multiply() writes A).
    virtual void pattern_into(SparseMatrix& M) const { M = make_matrix(); }
    /// Into K (reduced, from make_matrix(); may be null) the stiffness, into f_int (3#rows,
    /// resized; may be null) the elastic forces [N] at x. Corotated mode updates the cached
    /// cell rotations.
    virtual void assemble(const MatX3& x, ForceMode mode, SparseMatrix* K, VecX* f_int) = 0;
    /// The implicit step's matrix without a pass over K: into A (reduced, from make_matrix())
    /// scale * K at x plus `diagonal` (#free, e.g. the step's mass term) on its diagonal, into
    /// f_int (3#rows) the elastic forces as assemble(), and into kv (3#rows, resized) scale * K v,
    /// with v (#rows x 3) the velocities [m/s], zero at fixed DOFs. Returns false, changing
    /// nothing, where the model cannot (the caller then assembles K and forms A from it).
    virtual bool assemble_step(const MatX3& /*x*/, ForceMode /*mode*/, double /*scale*/,
        const VecX& /*diagonal*/, const MatX3& /*v*/, SparseMatrix& /*A*/, VecX& /*f_int*/,
        VecX& /*kv*/) {
        return false;
    }
    /// Corotated stiffness re-linearized in turns (IntegratorOptions::stiffness_every = period):
    /// in K, assembled earlier by a full corotated assemble() and turned since, the terms of the
    /// cells c with c % period == phase move to the rotations at x, the other cells' terms stay;
    /// f_int is assembled in full at x. The same lag as re-assembling all of K every period
    /// steps, spread over the steps instead of spiking one of them. Returns false, changing
    /// nothing, where the model cannot (the caller then re-assembles K every period steps).
    virtual bool assemble_in_turns(
        const MatX3& /*x*/, SparseMatrix& /*K*/, VecX& /*f_int*/, int /*phase*/, int /*period*/) {
        return false;
    }
    /// Elastic energy [J] at x, consistent with the forces of `mode`.
    virtual double elastic_energy(const MatX3& x, ForceMode mode) const = 0;
    /// Per cell, the squared stretch at x (1 at rest and under rigid motion; +inf for
    /// non-finite values), resized to #cells.
    virtual void cell_stretch_squared(const MatX3& x, std::vector<double>& out) const = 0;
    /// The largest per-cell stretch at x.
    virtual double max_cell_stretch(const MatX3& x) const = 0;

    /// Incremented whenever the pattern (and DOF numbering) changes.
    virtual std::uint64_t topology_version() const = 0;
    /// Whether row ids are the same as at topology version `version`.
    virtual bool nodes_kept_since(std::uint64_t version) const = 0;
    /// When the rows were renumbered exactly once since topology version `version` and the
    /// renumbering is known: old row id -> id now (kNone: removed). Null otherwise (also when
    /// nodes_kept_since(version): nothing to map).
    virtual const std::vector<Index>* node_map_since(std::uint64_t) const { return nullptr; }
    /// Incremented whenever cell data or fixed DOFs change (a cached stiffness is stale).
    virtual std::uint64_t cell_version() const = 0;
    /// Threads for assemble() (>= 1); a model may ignore it.
    virtual void set_threads(int threads) = 0;
    virtual int threads() const = 0;
    /// Whether the rows are points in space whose coordinates an AMG solver may use for its
    /// rigid-body modes (true for nodes, false for polynomial coefficients).
    virtual bool rows_are_points() const { return true; }
    /// Starts of strongly coupled blocks of reduced DOFs (ascending, first 0, last #free), for
    /// a block-Jacobi preconditioner; empty: none (3x3 node blocks serve).
    virtual std::vector<long> dof_blocks() const { return {}; }
    /// Prolongation (#free x nc) from a coarse space to the reduced DOFs, for a two-level
    /// preconditioner (DG: the continuous P1 field on the mesh nodes, docs/decisions/0024);
    /// empty: none.
    virtual SparseMatrix coarse_space() const { return {}; }
};

} // namespace polycut::elasticity
