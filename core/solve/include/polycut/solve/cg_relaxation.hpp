// Matrix-free conjugate-gradient static relaxation with fixed degrees of freedom
// (Nienhuys, seed 002 sec. 3.1): K u = f_ext is solved on the affine subspace where the fixed
// DOFs keep their values, using only products K d.
#pragma once

#include "polycut/solve/sparse.hpp"

#include <functional>
#include <vector>

namespace polycut::solve {

/// Outcome of a relaxation.
struct RelaxationResult {
    int iterations = 0;
    double relative_residual = 0; ///< ||r|| / reference, r = f_ext - K u zeroed at fixed DOFs
    bool converged = false;
    /// The CG search direction met d^T K d <= 0 (K not positive definite on the free DOFs).
    bool breakdown = false;
};

/// Product K x (3m), e.g. minus the elastic force of displacement x. Kx is pre-sized to x.
using StiffnessProduct = std::function<void(const Vector& x, Vector& Kx)>;

/// Stateful relaxation: keeps its work vectors between calls (no allocation once the size is
/// stable). Not thread-safe.
class CgRelaxation {
public:
    /// Relaxes u toward K u = f_ext (002 eq. 3.6) with u fixed where fixed_dof is true.
    /// apply_K: the product K x; f_ext: external nodal forces (3m) [N]; fixed_dof: 3m flags;
    /// u: displacements (3m) [m], initial guess in, result out (fixed entries never change).
    /// Stops when ||r|| < tol ||f_ext|| (free DOFs only) or after max_iterations; if f_ext
    /// vanishes on the free DOFs (motion driven by prescribed displacements only), the
    /// reference is the initial residual instead.
    RelaxationResult relax(const StiffnessProduct& apply_K, const Vector& f_ext,
        const std::vector<bool>& fixed_dof, Vector& u, double tol, int max_iterations);

private:
    Vector m_r, m_d, m_q;
};

/// One-off form of CgRelaxation::relax (allocates its work vectors).
RelaxationResult cg_relax(const StiffnessProduct& apply_K, const Vector& f_ext,
    const std::vector<bool>& fixed_dof, Vector& u, double tol, int max_iterations);

} // namespace polycut::solve
