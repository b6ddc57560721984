// Isotropic Hookean material with Rayleigh damping.
#pragma once

#include <Eigen/Core>

namespace polycut::elasticity {

/// Isotropic linear elastic material, lumped-mass density and Rayleigh damping D = alpha M +
/// beta K.
struct Material {
    double youngs_modulus = 1e4; ///< E [Pa], > 0
    double poisson_ratio = 0.3; ///< nu, in (-1, 0.5)
    double density = 1000; ///< rho [kg/m^3], >= 0
    double rayleigh_mass = 0; ///< alpha [1/s], >= 0
    double rayleigh_stiffness = 0; ///< beta [s], >= 0

    /// Shear modulus mu = E / (2 (1 + nu)) [Pa].
    double mu() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
    /// First Lame parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa].
    double lambda() const {
        return youngs_modulus * poisson_ratio
            / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
    }
};

/// Throws InputError naming the field ("youngs_modulus", ...) if a value is out of range or not
/// finite.
void validate(const Material& material);

/// Isotropic elasticity matrix C (6 x 6) [Pa] in Voigt order (xx, yy, zz, yz, xz, xy) with
/// engineering shear strains.
Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& material);

} // namespace polycut::elasticity
