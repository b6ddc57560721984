// Options of core/elasticity: the material and the force model. Plain data in the options layer
// (docs/decisions/0051), the one place their defaults live: core/scene reads scene files into
// these types and takes its defaults from them.
#pragma once

namespace polycut::elasticity {

/// Isotropic linear elastic material, lumped-mass density and Rayleigh damping D = alpha M +
/// beta K.
struct Material {
    double youngs_modulus = 1e4; ///< E [Pa], > 0
    double poisson_ratio = 0.45; ///< nu, in (-1, 0.5); soft tissue (docs/decisions/0051)
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

/// How elastic forces and stiffness are evaluated.
enum class ForceMode {
    Linear, ///< small-strain linear elasticity, K constant
    Corotated, ///< per-cell rotation from the affine fit's polar decomposition
};

} // namespace polycut::elasticity
