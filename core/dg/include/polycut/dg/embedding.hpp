// The surface of a DG field (003 sec. 8): the displacement is discontinuous between cells, so
// nothing is drawn from it directly. Stitching (003 eq. 17) averages, at every mesh node, the
// displacements u|_K(x_i) of the cells K that contain it; the continuous nodal field is what
// the mesh's own boundary surface (the streamed surface, the VTU output) shows, so that surface
// cannot crack. MLS (003 eq. 18-19) carries the stitched field to points that are not nodes
// (probes, sampled points, an embedded render surface): per point an affine fit
// a(x)^T (1, x, y, z) to the nearby stitched nodes under truncated Gaussian weights, which
// reproduces affine fields (rigid motions) exactly. Both are linear in the coefficients and
// precomputed as sparse maps (003 eq. 19), so evaluating them per frame is one sparse product.
#pragma once

#include "polycut/common/sparse.hpp"
#include "polycut/common/types.hpp"

#include <vector>

namespace polycut::dg {

class DgModel;

/// 003 eq. 17 as a sparse map S (#nodes x #coeffs): u~ = S (x - X0). Nodes no cell uses get 0.
class Stitching {
public:
    explicit Stitching(const DgModel& model);

    const SparseMatrix& matrix() const { return m_S; }
    /// Stitched nodal displacements (#nodes x 3) [m] from generalised positions x (#coeffs x 3).
    void displacements(const MatX3& x, MatX3& u) const;
    /// Nodal world positions X_i + u~_i (#nodes) [m].
    void positions(const MatX3& x, std::vector<Vec3>& out) const;
    /// The adjoint: nodal forces (3#nodes) [N] to coefficient loads (3#coeffs) [N], so that the
    /// work of a force on a stitched node equals the work of the load on the coefficients.
    void loads(const VecX& nodal_forces, VecX& coefficient_loads) const;
    /// Whether node i belongs to a cell.
    bool used(Index node) const { return m_used[std::size_t(node)] != 0; }

private:
    const DgModel* m_model;
    SparseMatrix m_S;
    std::vector<std::uint8_t> m_used;
};

/// 003 eq. 18-19 for a fixed set of rest points: weights W (#points x #nodes) with
/// u(p) = sum_i W(p, i) u~_i. The support of point p is rho = `support` times the diameter of
/// the nearest cell, grown (doubled, up to 4 times) until the weighted moment matrix of
/// (1, x - p) is well conditioned; theta(d) = exp(-(3 d / rho)^2) for d < rho.
class MlsEmbedding {
public:
    MlsEmbedding(const DgModel& model, const std::vector<Vec3>& points, double support = 1.5);

    const SparseMatrix& weights() const { return m_W; }
    /// Displacements (#points x 3) [m] from stitched nodal displacements (#nodes x 3).
    void displacements(const MatX3& stitched, MatX3& u) const;

private:
    SparseMatrix m_W;
};

} // namespace polycut::dg
