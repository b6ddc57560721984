// Isotropic Hookean material with Rayleigh damping.
#pragma once

#include "polycut/options/elasticity.hpp"

#include <Eigen/Core>

namespace polycut::elasticity {

/// Throws InputError naming the field ("youngs_modulus", ...) if a value is out of range or not
/// finite.
void validate(const Material& material);

/// Isotropic elasticity matrix C (6 x 6) [Pa] in Voigt order (xx, yy, zz, yz, xz, xy) with
/// engineering shear strains.
Eigen::Matrix<double, 6, 6> elasticity_matrix(const Material& material);

} // namespace polycut::elasticity
