#include "polycut/integrate/stability.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace polycut::integrate {

StabilityLimit semi_implicit_limit(const elasticity::ElasticModel& model) {
    StabilityLimit out;
    const auto& mat = model.material();
    const Index cells = model.mesh().num_cells();
    double omega2 = 0;
    for (Index c = 0; c < cells; ++c) {
        const auto K = model.cell_stiffness(c);
        const VecX& lumped = model.cell_integration(c).lumped_volume;
        if (K.rows() == 0 || lumped.size() * 3 != K.rows())
            continue;
        VecX inv_sqrt_m(K.rows());
        for (Index i = 0; i < lumped.size(); ++i) {
            const double m = mat.density * lumped(i);
            if (!(m > 0)) {
                out.critical_dt = 0;
                out.omega_max = std::numeric_limits<double>::infinity();
                return out;
            }
            inv_sqrt_m.segment<3>(3 * i).setConstant(1.0 / std::sqrt(m));
        }
        const MatX A = inv_sqrt_m.asDiagonal() * K * inv_sqrt_m.asDiagonal();
        const Eigen::SelfAdjointEigenSolver<MatX> eig(A, Eigen::EigenvaluesOnly);
        omega2 = std::max(omega2, eig.eigenvalues().maxCoeff());
    }
    // lambda_max(K_cells + K_vol) <= the two bounds' sum (nodal volumetric term; 0 otherwise)
    out.omega_max = std::sqrt(omega2 + model.nodal_volumetric_omega2());
    if (!(out.omega_max > 0)) {
        out.critical_dt = std::numeric_limits<double>::infinity();
        return out;
    }
    const double w = out.omega_max;
    const double xi = (mat.rayleigh_mass + mat.rayleigh_stiffness * w * w) / (2 * w);
    out.critical_dt = 2.0 / w / (std::sqrt(1 + xi * xi) + xi); // = (2 / w)(sqrt(1 + xi^2) - xi)
    return out;
}

} // namespace polycut::integrate
