#include "polycut/elasticity/material.hpp"

#include "polycut/common/error.hpp"

#include <cmath>

namespace polycut::elasticity {

void validate(const Material& m) {
    if (!std::isfinite(m.youngs_modulus) || m.youngs_modulus <= 0)
        throw InputError("youngs_modulus", "Young's modulus must be finite and > 0 Pa");
    if (!std::isfinite(m.poisson_ratio) || m.poisson_ratio <= -1 || m.poisson_ratio >= 0.5)
        throw InputError("poisson_ratio", "Poisson's ratio must lie in (-1, 0.5)");
    if (!std::isfinite(m.density) || m.density < 0)
        throw InputError("density", "density must be finite and >= 0 kg/m^3");
    if (!std::isfinite(m.rayleigh_mass) || m.rayleigh_mass < 0)
        throw InputError("rayleigh_mass", "Rayleigh alpha must be finite and >= 0 1/s");
    if (!std::isfinite(m.rayleigh_stiffness) || m.rayleigh_stiffness < 0)
        throw InputError("rayleigh_stiffness", "Rayleigh beta must be finite and >= 0 s");
}

Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& m) {
    const double mu = m.mu(), lambda = m.lambda();
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    C.topLeftCorner<3, 3>().setConstant(lambda);
    for (int i = 0; i < 3; ++i) {
        C(i, i) = lambda + 2 * mu;
        C(i + 3, i + 3) = mu;
    }
    return C;
}

} // namespace polycut::elasticity
