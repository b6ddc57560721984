// Stability limits of the explicit parts of the integrators (issue 17 item 4): a scene whose
// time step an integrator cannot take is refused at load with the limit, not run into NaN.
#pragma once

#include "polycut/elasticity/elastic_model.hpp"

namespace polycut::integrate {

/// Frequency bound and time-step limit of semi-implicit (symplectic) Euler on a model.
struct StabilityLimit {
    /// Upper bound of the model's highest angular frequency [rad/s]: the largest element
    /// frequency, omega_e^2 = lambda_max(M_e^-1/2 K_e M_e^-1/2) with M_e the cell's share of the
    /// lumped mass (Irons' element eigenvalue bound; fixed DOFs only lower the true value).
    double omega_max = 0;
    /// Largest stable step [s]: for a mode of frequency w with Rayleigh damping
    /// c = alpha + beta w^2, symplectic Euler is stable iff h^2 w^2 + 2 h c <= 4, i.e.
    /// h <= (2 / w) (sqrt(1 + xi^2) - xi), xi = c / (2 w), evaluated at omega_max (the
    /// limit falls as w grows). Infinite for a model without cells; 0 if a cell has no mass.
    double critical_dt = 0;
};

/// The semi-implicit Euler limit of `model` with its material's density and damping. Costs one
/// small symmetric eigenproblem per cell (about 10 us for a tet).
StabilityLimit semi_implicit_limit(const elasticity::ElasticModel& model);

} // namespace polycut::integrate
