// Penalty forces on material points (contact, issue 15 item 1) and how their stiffness enters
// the implicit system. A material point p = sum_i w_i x_i (a node, or an embedded point with its
// cell's basis weights) feels a force linear in its position and velocity around the state x_n
// the step starts from:
//     f(p, pdot) = f0 - K (p - p_n) - D (pdot - v_other),
// K and D symmetric positive semi-definite 3x3 blocks. Node i gets w_i f, so the force's
// Jacobian adds w_i w_j K to the (i, j) 3x3 block of the stiffness (003 eq. 20-21:
// K_ij -= W_i A W_j, F_i += b W_i). Point-to-node weights of one point belong to one cell, so
// every block falls on the elastic sparsity pattern. With p_{n+1} - p_n = h pdot_{n+1}, implicit
// Euler gets + h^2 K + h D in its matrix and h (f0 - h K pdot_n - D (pdot_n - v_other)) on the
// right, as the grab springs do (springs.hpp).
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/solve/sparse.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace polycut::integrate {

/// One material point under a penalty force.
struct PenaltyPoint {
    std::uint32_t first = 0; ///< its first entry in PenaltySet::nodes / weights
    std::uint32_t count = 0; ///< number of nodes it is spread over
    Vec3 force = Vec3::Zero(); ///< f0 at the linearization point [N]
    Mat3 stiffness = Mat3::Zero(); ///< K = -df/dp, symmetric PSD [N/m]
    Mat3 damping = Mat3::Zero(); ///< D = -df/dpdot, symmetric PSD [N s/m] (friction)
    Vec3 other_velocity = Vec3::Zero(); ///< velocity of the body it touches at p [m/s]
};

/// The penalty points of one evaluation.
struct PenaltySet {
    std::vector<Index> nodes; ///< node ids of every point, point after point
    std::vector<double> weights; ///< weight of each entry of `nodes`
    std::vector<PenaltyPoint> points;
    void clear() {
        nodes.clear();
        weights.clear();
        points.clear();
    }
};

/// A source of penalty points (core/contact implements it). The integrator calls it inside
/// every (sub)step, at the positions the step linearizes at, so the set always belongs to the
/// state it is applied to. Must not throw from evaluate(); non-finite input gives no points.
class PenaltyField {
public:
    virtual ~PenaltyField() = default;
    /// The points in contact over a step of length h [s] from positions `x` (#N x 3) [m] and
    /// velocities `v` (#N x 3) [m/s]: those inside a body at x or at the predicted x + h v (a
    /// point about to enter is caught in the step that takes it there; one leaving is held
    /// for that step instead of bouncing off with the velocity that pushed it out). Forces
    /// and blocks are linearized at x (f0 may pull for a point still outside: the linear model
    /// of the penalty that the step brings it into). h = 0: static, active at x only.
    /// Replaces `out`.
    virtual void evaluate(const MatX3& x, const MatX3& v, double h, PenaltySet& out) = 0;
    /// Penalty energy at positions `x` [J] (the potential of the non-friction part; the energy
    /// guard counts it like gravity).
    virtual double energy(const MatX3& x) const = 0;
};

/// Adds the reduced nodal forces of `set` times `scale` to `f_r` (#free) [N]; with velocities
/// `v` (#N x 3) [m/s], the force is f0 - h K pdot - D (pdot - v_other) (the step's right-hand
/// side), without, f0.
void add_penalty_forces(const PenaltySet& set, const MatX3* v, double h,
    const std::vector<Index>& dof_map, double scale, VecX& f_r);

/// A += sum over points of w_i w_j (cK K + cD D) on the free DOFs, into the (i, j) blocks of
/// A's existing pattern (full symmetric storage). Each addition is appended to `record` as
/// (index into A.valuePtr(), value) so that undo_penalty_blocks() can take it out again; an
/// entry missing from the pattern is skipped and counted in the return value.
std::size_t add_penalty_blocks(const PenaltySet& set, const std::vector<Index>& dof_map, double cK,
    double cD, solve::SparseMatrix& A, std::vector<std::pair<Index, double>>& record);

/// Subtracts what add_penalty_blocks() recorded and clears the record.
void undo_penalty_blocks(solve::SparseMatrix& A, std::vector<std::pair<Index, double>>& record);

/// Per-node 3x3 blocks sum over points of w_i^2 (cK K + cD D) (the cross-node coupling
/// dropped), for integrators that only solve per node (semi-implicit Euler). `blocks` is
/// resized to #N; untouched nodes stay zero.
void penalty_node_blocks(
    const PenaltySet& set, Index num_nodes, double cK, double cD, std::vector<Mat3>& blocks);

} // namespace polycut::integrate
