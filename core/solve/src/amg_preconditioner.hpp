// Private: one BoomerAMG V-cycle as a PCG preconditioner (hypre behind a pimpl; this header is
// free of hypre and MPI so pcg.cpp need not see them).
#pragma once

#include "polycut/solve/amg_options.hpp"
#include "polycut/solve/sparse.hpp"

#include <memory>
#include <string>

namespace polycut::solve::detail {

class AmgPreconditioner {
public:
    explicit AmgPreconditioner(AmgOptions options);
    ~AmgPreconditioner();
    AmgPreconditioner(const AmgPreconditioner&) = delete;
    AmgPreconditioner& operator=(const AmgPreconditioner&) = delete;

    /// Builds the multigrid hierarchy of A (symmetric, full storage, n x n): hypre keeps a copy,
    /// so A may change afterwards (the hierarchy is then lagged). NonFinite on NaN/Inf in A,
    /// NotPositiveDefinite on a non-positive diagonal entry, NotReady if hypre/MPI is unusable
    /// (reason in error()).
    SolveStatus setup(const SparseMatrix& A);
    /// z = M^-1 r by one V-cycle from z = 0 (r, z: n). A: the current system matrix (the
    /// set-up's pattern; the fused cycle smooths the finest level with it, hypre's cycle ignores
    /// it). NotReady before a successful setup() or on size mismatch; NonFinite if z is not
    /// finite.
    SolveStatus apply(const SparseMatrix& A, const Vector& r, Vector& z);
    /// The next apply()'s matrix has new values (a new solve): the fused cycle refreshes its
    /// copy of the finest level then (amg_cycle.hpp, "Node blocks"). Call once per solve.
    void matrix_changed();
    /// Threads for the fused cycle's finest level (hybrid Gauss-Seidel, amg_cycle.hpp); 1 =
    /// serial. hypre's own cycle stays serial.
    void set_threads(int threads);
    /// Size of the matrix of the last successful setup (-1 if none).
    long size() const;
    /// Number of levels of the current hierarchy (0 if none).
    int levels() const;
    /// Levels the fused cycle smooths on several threads (0: serial or hypre's cycle).
    int threaded_levels() const;
    /// Node coordinates for the rigid-body modes (AmgOptions::rigid_body_modes): per DOF the
    /// coordinate of its node along the DOF's component (n, interleaved like the DOFs) [m].
    /// Copied; used by the next setup() of a matrix of the same size. Empty: none.
    void set_coordinates(const Vector& coordinates);
    /// Why the last setup() returned NotReady.
    const std::string& error() const;
    /// Drops the hierarchy.
    void clear();
    /// Exchanges the hierarchies (and settings) of two preconditioners.
    void swap(AmgPreconditioner& other) noexcept { m_impl.swap(other.m_impl); }
    /// Keeps the hierarchy for a matrix whose unknowns a cut renumbered (see RowRemap and
    /// AmgCycle::remap). False (hierarchy unchanged) when not possible (hypre's own
    /// cycle, no coarse level): set up again then.
    bool remap(const RowRemap& m);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace polycut::solve::detail
