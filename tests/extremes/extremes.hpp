// Shared by the extremes tests (issue 17 item 4): scenes built as JSON text, and one watcher
// that steps a simulation and checks after every step what every case must hold: no non-finite
// value, no rollback storm, total energy not growing while nothing drives the tissue (damped
// scenes), and the free-fall bound under gravity.
#pragma once

#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>
#include <string>

namespace polycut::extremes {

constexpr double kG = 9.81; ///< |gravity| [m/s^2]

/// What a run may do, and what it did.
struct Watch {
    // Checks
    double dt = 0.01; ///< the scene's step [s] (0: static)
    bool gravity_only = true; ///< gravity is the only load: the free-fall bound applies
    bool undriven = true; ///< no input changes the energy but gravity (forces, grabs: false)
    /// Relative growth of the total energy (kinetic + elastic + gravity potential) allowed per
    /// step, against the largest energy magnitude seen; corotated forces are linearized once per
    /// step, so a large rotation can add round-off-sized energy, never a blow-up.
    double energy_slack = 1e-6;
    int max_rollbacks = 0; ///< steps that may be rolled back (the rest must succeed)
    double mass = 0; ///< total mass [kg] for the centre-of-mass free-fall bound (0: skip it)
    // Results
    int steps = 0;
    int rollbacks = 0;
    int undone = 0;
    double max_displacement = 0; ///< largest node displacement seen [m]
    double max_drop = 0; ///< largest node displacement along gravity (-z) seen [m]
    double worst_energy_rise = 0; ///< largest relative rise of the total energy in one step
    std::string first_warning;
};

/// Steps `sim` `n` times, checking each step; returns false (with gtest failures) on the first
/// violated check. `rest` are the rest positions (the positions before the first step).
bool step_and_check(sim::Simulation& sim, int n, Watch& w, const std::vector<Vec3>& rest);

/// Positions at construction: the rest positions of the initial mesh.
inline std::vector<Vec3> rest_of(const sim::Simulation& s) {
    return s.positions();
}

/// The beam of the sweeps: [0, 0.4] x [0, 0.1] x [0, 0.1] m, clamped at x = 0, under gravity,
/// Rayleigh damping alpha = 1 /s, beta = 1e-3 s; probe "tip" at (0.4, 0.05, 0.05).
/// `method`: "tet", "hex", "hex_bbar" (Q1 with mean dilatation), "mvc", "harmonic" (the last
/// two on random-plane polyhedra, 2 planes per block).
std::string beam_scene(const std::string& method, double nu, double E, double dt,
    const std::string& integrator = "implicit_euler", bool energy_guard = true);

/// Euler-Bernoulli tip deflection of the beam under its own weight, q L^4 / (8 E I) [m].
double beam_static_sag(double E);

} // namespace polycut::extremes
