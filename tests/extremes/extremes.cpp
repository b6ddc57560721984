#include "extremes.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace polycut::extremes {

bool step_and_check(sim::Simulation& sim, int n, Watch& w, const std::vector<Vec3>& rest) {
    double energy = sim.energy().total();
    double scale = std::abs(energy);
    for (int i = 0; i < n; ++i) {
        const sim::StepReport r = sim.step();
        ++w.steps;
        w.rollbacks += r.rolled_back ? 1 : 0;
        w.undone += r.cut_undone ? 1 : 0;
        if (!r.warnings.empty() && w.first_warning.empty())
            w.first_warning = r.warnings.front();
        const auto& x = sim.positions();
        for (std::size_t k = 0; k < x.size(); ++k) {
            if (!x[k].allFinite()) {
                ADD_FAILURE() << "non-finite position at step " << w.steps;
                return false;
            }
            if (k < rest.size()) {
                w.max_displacement = std::max(w.max_displacement, (x[k] - rest[k]).norm());
                w.max_drop = std::max(w.max_drop, rest[k].z() - x[k].z());
            }
        }
        if (w.rollbacks > w.max_rollbacks) {
            ADD_FAILURE() << "rollback storm: " << w.rollbacks << " rolled-back steps by step "
                          << w.steps << " (allowed " << w.max_rollbacks << "): " << w.first_warning;
            return false;
        }
        const sim::Energy e = sim.energy();
        if (w.gravity_only && w.dt > 0) {
            // Free fall after n steps of backward Euler: g h^2 n (n + 1) / 2. Supports and
            // elastic forces hold the tissue back: its centre of mass falls no further (the
            // gravity potential is -m g . u_c, so the drop is gravity / (m g)). A single node may
            // fall faster: the tip of a hinged rod released horizontally starts at 3/2 g, so a
            // node's drop (along g = -z) is bounded by 1.5 x free fall (measured: 1.03 x).
            const double t = w.steps * w.dt;
            const double fall = 0.5 * kG * t * (t + w.dt);
            if (w.mass > 0 && -e.gravity / (w.mass * kG) > fall * (1 + 1e-6) + 1e-12) {
                ADD_FAILURE() << "the centre of mass fell " << -e.gravity / (w.mass * kG)
                              << " m, more than free fall " << fall << " m at step " << w.steps;
                return false;
            }
            if (w.max_drop > 1.5 * fall + 1e-12) {
                ADD_FAILURE() << "a node fell " << w.max_drop << " m, more than 1.5 x free fall "
                              << fall << " m at step " << w.steps;
                return false;
            }
        }
        const double now = e.total();
        if (!std::isfinite(now)) {
            ADD_FAILURE() << "non-finite energy at step " << w.steps;
            return false;
        }
        scale = std::max({ scale, std::abs(now), e.kinetic, e.elastic, std::abs(e.gravity) });
        if (w.undriven && scale > 0) {
            const double rise = (now - energy) / scale;
            w.worst_energy_rise = std::max(w.worst_energy_rise, rise);
            if (rise > w.energy_slack) {
                ADD_FAILURE() << "total energy rose by " << rise << " of its scale at step "
                              << w.steps << " (" << energy << " -> " << now << " J)";
                return false;
            }
        }
        energy = now;
    }
    return true;
}

std::string beam_scene(const std::string& method, double nu, double E, double dt,
    const std::string& integrator, bool guard) {
    std::ostringstream s;
    s.precision(17);
    const bool polyhedra = method == "mvc" || method == "harmonic";
    const bool hex = method == "hex" || method == "hex_bbar";
    s << R"({"name": "beam", "geometry": {"type": ")" << (polyhedra ? "random_planes" : "box")
      << R"(", "origin": [0, 0, 0], "size": [0.4, 0.1, 0.1], "cells": [4, 1, 1], )";
    if (polyhedra)
        s << R"("planes_per_cell": 2, "seed": 3},)";
    else
        s << R"("elements": ")" << (hex ? "hex" : "tet") << R"("},)";
    s << R"( "method": ")" << (method == "hex_bbar" ? "hex" : method) << R"(",)";
    s << R"( "basis": {"rule": "reference", "volumetric": ")"
      << (method == "hex_bbar" ? "mean_dilatation" : "full") << R"("},)";
    s << R"( "material": {"youngs_modulus": )" << E << R"(, "poisson_ratio": )" << nu
      << R"(, "density": 1000, "rayleigh_mass": 1.0, "rayleigh_stiffness": 0.001},)";
    s << R"( "integrator": {"type": ")" << integrator << R"(", "dt": )" << dt
      << R"(, "corotated": true, "energy_guard": )" << (guard ? "true" : "false")
      << R"(}, "solver": {"type": "cholmod"},)";
    s << R"( "fixed": [{"plane": {"point": [0, 0, 0], "normal": [1, 0, 0]}}],
      "loads": {"gravity": [0, 0, -9.81]},
      "probes": [{"name": "tip", "point": [0.4, 0.05, 0.05]}]})";
    return s.str();
}

double beam_static_sag(double E) {
    const double rho = 1000, A = 0.01, L = 0.4, I = 0.1 * std::pow(0.1, 3) / 12;
    return rho * kG * A * std::pow(L, 4) / (8 * E * I);
}

} // namespace polycut::extremes
