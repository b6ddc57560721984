// Dense least-squares solve of the MFS collocation systems (seed 001 eq. 14) shared by the 2D
// face and 3D cell problems, and the exact linear-reproduction correction of 001 sec. 5.
//
// The systems are tall (m ~ 3n rows) and the QR factorization (2 m n^2 flops) dominates the
// set-up of a harmonic cell. The normal equations need half the flops in a symmetric rank-k
// update that runs at matrix-product speed, and after scaling the columns to unit norm their
// Cholesky factor is accurate enough that one step of iterative refinement (the "corrected
// semi-normal equations", Bjorck 1996 sec. 2.9) brings the residual to the QR one.
#include "harmonic_detail.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace polycut::basis::detail {
namespace {
/// Least squares by Cholesky of the column-scaled normal equations with one refinement step;
/// empty when the normal matrix is not numerically positive definite.
MatX solve_normal_equations(MatX& A, const MatX& B) {
    const Index c = Index(A.cols());
    VecX inv_scale(c);
    for (Index j = 0; j < c; ++j) {
        const double s = A.col(j).norm();
        inv_scale[j] = s > 0 ? 1.0 / s : 1.0;
        A.col(j) *= inv_scale[j];
    }
    MatX N = MatX::Zero(c, c);
    N.selfadjointView<Eigen::Lower>().rankUpdate(A.transpose());
    const Eigen::LLT<MatX, Eigen::Lower> llt(N);
    if (llt.info() != Eigen::Success || !(llt.rcond() > 1e-15))
        return {};
    MatX Y = llt.solve(A.transpose() * B);
    const MatX residual = B - A * Y;
    Y += llt.solve(A.transpose() * residual);
    return inv_scale.asDiagonal() * Y;
}
} // namespace

MatX solve_mfs(MatX A, const MatX& B, const MatX& X, Index num_kernels, HarmonicSolver solver) {
    MatX coef;
    if (solver == HarmonicSolver::NormalEquations) {
        MatX scaled = A; // keep A for the QR fallback
        coef = solve_normal_equations(scaled, B);
    }
    // Householder QR (001 eq. 14: "QR factorization"); kernels are placed at least a fraction
    // of their spacing apart, so the columns stay independent. A column-pivoted QR takes over
    // if the result is not finite.
    if (coef.size() == 0 || !coef.allFinite())
        coef = Eigen::HouseholderQR<MatX>(A).solve(B);
    if (!coef.allFinite())
        coef = Eigen::ColPivHouseholderQR<MatX>(A).solve(B);
    // Reproduction constraint: with nodal coordinates X (g x (d+1)), the combination
    // coef * X must be exactly the polynomial [x, 1] (kernel weights zero, polynomial identity).
    const Index n = num_kernels;
    const Index d1 = Index(X.cols());
    const MatX XtXinv_Xt = (X.transpose() * X).ldlt().solve(X.transpose()); // (d+1) x g
    auto W = coef.topRows(n);
    W -= (W * X) * XtXinv_Xt;
    auto P = coef.bottomRows(d1);
    const MatX defect = MatX::Identity(d1, d1) - P * X;
    P += defect * XtXinv_Xt;
    return coef;
}

} // namespace polycut::basis::detail
