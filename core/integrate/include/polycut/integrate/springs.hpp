// Zero-length penalty springs from nodes to world-space anchors (grabs, and any penalty force
// to come), treated implicitly: their stiffness enters the system matrix of every integrator
// that solves one, so a spring is stable for any stiffness (issue 14 item 2). A spring's force
// Jacobian is -k I on its own node's diagonal block, so it fits any sparsity pattern.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/solve/sparse.hpp"

#include <vector>

namespace polycut::integrate {

/// f = stiffness (anchor - x_node) on one node [N].
struct NodeSpring {
    Index node = 0; ///< node index (#N numbering of the model)
    Vec3 anchor = Vec3::Zero(); ///< world-space rest point of the spring [m]
    double stiffness = 0; ///< [N/m], > 0
};

/// Adds the reduced spring forces at positions `x` (#N x 3) [m] to `f_r` (#free) [N]. Springs
/// on fixed DOFs act on nothing.
void add_spring_forces(const std::vector<NodeSpring>& springs, const MatX3& x,
    const std::vector<Index>& dof_map, VecX& f_r);

/// The reduced diagonal of the springs' stiffness (#free) [N/m]: k on each free DOF of a sprung
/// node, summed over the springs on it; zero elsewhere.
void spring_diagonal(const std::vector<NodeSpring>& springs, const std::vector<Index>& dof_map,
    Index n_free, VecX& diagonal);

/// Elastic energy of the springs at positions `x` (#N x 3) [J], fixed DOFs included.
double spring_energy(const std::vector<NodeSpring>& springs, const MatX3& x);

/// A(i, i) += d(i) for every i with d(i) != 0 (the diagonal must be stored, as it is for every
/// free DOF of a model with positive mass or stiffness).
void add_to_diagonal(solve::SparseMatrix& A, const VecX& d);

} // namespace polycut::integrate
