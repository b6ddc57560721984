// Harmonic shape functions on convex and non-convex polyhedra with planar faces (seed 001 sec.
// 4-5), discretized by the method of fundamental solutions with a linear polynomial term
// (001 eq. 11-14): first per face in 2D (log kernel) for the boundary values, then in 3D (1/r
// kernel) with one factorization per cell and one right-hand side per node.
#pragma once

#include "polycut/basis/cell_geometry.hpp"
#include "polycut/basis/cell_integration.hpp"
#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace polycut::basis {

/// How the dense least-squares collocation systems (001 eq. 14) are solved.
enum class HarmonicSolver {
    /// Cholesky of the column-scaled normal equations plus one step of iterative refinement
    /// (corrected semi-normal equations): ~3-5x faster than QR at the same residual; falls back
    /// to QR when the normal matrix is not numerically positive definite.
    NormalEquations,
    QR, ///< Householder QR of the collocation matrix (001 eq. 14)
};

/// Discretization parameters of the harmonic basis (001 sec. 5).
struct HarmonicOptions {
    /// Kernel offset xi of 001 eq. 12, as a fraction of the cell (face) bounding-box diagonal.
    /// 001 uses 0.1; with the coarser face grid (face_spacing) 0.15 is more accurate on convex
    /// cells (box: 1.7 % boundary error instead of 2.9 %; docs/perf.md).
    double offset = 0.15;
    /// Upper bound of the offset of non-convex cells (001's 0.1).
    double nonconvex_offset = 0.1;
    /// Kernel samples inside each edge (001: "about 3-5 samples on each edge"); faces are
    /// sampled at about the same spacing.
    int edge_samples = 3;
    /// Spacing of the face-interior kernels relative to the edge kernels' (>= 1). 001 samples
    /// faces "of about the same density" (1); 1.5 needs ~2x fewer kernels for ~1 % more
    /// boundary error (docs/perf.md), and the set-up cost grows with the cube of the count.
    double face_spacing = 1.5;
    /// Collocation density relative to the kernels (001 eq. 13: m ~ 3n); face collocation
    /// points are spaced hk sqrt(face_spacing / collocation_ratio), hk the edge kernel spacing.
    double collocation_ratio = 3.0;
    /// Nodes closer than this fraction of the size are merged into one joint basis function
    /// (001 sec. 5, "degenerate edges"), shared equally between them.
    double merge_tolerance = 1e-9;
    /// Least-squares solver of the face and cell systems.
    HarmonicSolver solver = HarmonicSolver::NormalEquations;
};

/// How a harmonic cell is integrated.
enum class HarmonicRule {
    Gauss, ///< Gauss rule on a star tetrahedralization (from the centroid if it sees every face)
    MonteCarlo, ///< uniform random points in the cell, equal weights (for comparison)
};

/// Integration parameters.
struct HarmonicIntegration {
    HarmonicRule rule = HarmonicRule::Gauss;
    int gauss_degree = 2; ///< polynomial degree of the tet rule (>= 0)
    int monte_carlo_samples = 10000; ///< points inside the cell for HarmonicRule::MonteCarlo
    std::uint64_t seed = 1; ///< random seed for HarmonicRule::MonteCarlo
};

/// Boundary error of the 3D functions against their Dirichlet data (001 eq. 13), over test
/// points on the surface distinct from the collocation points, all basis functions together.
struct HarmonicBoundaryError {
    double rms
        = 0; ///< root mean square of (N_i - b_i) over points and i, relative to the RMS of b_i
    double max = 0; ///< largest |N_i - b_i| (absolute; the data lie in [0, 1])
};

/// Harmonic basis of one polyhedral cell. Immutable after construction; evaluate() is
/// thread-safe.
class HarmonicCell {
public:
    /// Solves the face and cell problems. Throws MeshError for fewer than 4 distinct nodes, a
    /// non-positive volume or a rank-deficient system.
    HarmonicCell(std::vector<Vec3> nodes, const std::vector<std::vector<Index>>& loops,
        const HarmonicOptions& options = {});
    explicit HarmonicCell(const CellGeometry& cell, const HarmonicOptions& options = {});
    ~HarmonicCell();
    HarmonicCell(HarmonicCell&&) noexcept;
    HarmonicCell& operator=(HarmonicCell&&) noexcept;

    /// Number of nodes (shape functions).
    Index num_nodes() const;
    /// Node positions (#n) [m].
    const std::vector<Vec3>& nodes() const;
    /// Number of 3D kernels n of 001 eq. 11 and of collocation points m of eq. 13.
    Index num_kernels() const;
    Index num_collocation() const;
    /// Cell volume [m^3] and bounding-box diagonal [m].
    double volume() const;
    double size() const;

    /// Values phi (#n) and optionally gradients (#n x 3) [1/m] at x [m] (anywhere away from the
    /// kernel centres; meaningful in the closed cell).
    void evaluate(const Vec3& x, VecX& phi, MatX3* grad = nullptr) const;

    /// Boundary values b (#n) at a surface point x [m] of face `face` (the loop index): the
    /// face's 2D harmonic coordinates (001 sec. 4, eq. 8).
    void boundary_values(Index face, const Vec3& x, VecX& b) const;

    /// Boundary error of the 3D functions against the face data, on `per_edge` test points per
    /// edge and a matching face density.
    HarmonicBoundaryError boundary_error(int per_edge = 10) const;

    /// Quadrature (points, weights, gradients) and lumped volumes int phi_i dV by `integration`.
    CellIntegration integrate(const HarmonicIntegration& integration = {}) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Integration of a harmonic cell (nodes, outward loops).
CellIntegration integrate_harmonic(const std::vector<Vec3>& nodes,
    const std::vector<std::vector<Index>>& loops, const HarmonicIntegration& integration = {},
    const HarmonicOptions& options = {});

/// Integration of cell `cell` of `mesh` with the harmonic basis; node order is Cell::nodes.
CellIntegration integrate_harmonic(const mesh::Mesh& mesh, Index cell,
    const HarmonicIntegration& integration = {}, const HarmonicOptions& options = {});

} // namespace polycut::basis
