// The implicit Euler step's energy guard (IntegratorOptions::energy_guard, issue 17 item 4,
// docs/decisions/0013): a step that gains energy is halved, and a gain no halving removes is
// taken out by shortening the step.
#include "polycut/integrate/integrator.hpp"
#include "polycut/integrate/springs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace polycut::integrate {

double Integrator::total_energy(const State& s) const {
    // Potential of gravity relative to rest: -G . (x - X0), G the model's gravity load.
    VecX load = VecX::Zero(3 * m_model->num_rows());
    m_model->add_gravity(m_options.gravity, load);
    const MatX3 u = s.x - m_rest;
    const double gravity = -load.dot(flat(u));
    // Grab springs are potential forces too (anchors fixed within a step): without their energy
    // every step toward a moved grab target read as a gain and was shortened to nothing.
    // Contact penalties likewise (obstacles and tools hold still within a step).
    // Kinetic + elastic: the expensive part (a polar decomposition per cell), reused when the
    // state and the model are those of the last evaluation: a step's start is the previous
    // step's end, so an accepted step costs one evaluation instead of two.
    GuardCache& c = m_guard_cache;
    const bool same = c.valid && c.cell_version == m_model->cell_version()
        && c.topology_version == m_model->topology_version() && c.x.rows() == s.x.rows()
        && c.v.rows() == s.v.rows() && c.x == s.x && c.v == s.v;
    if (!same) {
        c.energy = energy(s);
        c.x = s.x;
        c.v = s.v;
        c.cell_version = m_model->cell_version();
        c.topology_version = m_model->topology_version();
        c.valid = true;
    }
    return c.energy + gravity + spring_energy(m_springs, s.x)
        + (m_penalty ? m_penalty->energy(s.x) : 0.0);
}

bool Integrator::step_implicit_guarded(State& s, StepReport& report, double h, int depth) {
    if (m_guard_start.size() <= std::size_t(depth))
        m_guard_start.resize(std::size_t(depth) + 1);
    State& start = m_guard_start[std::size_t(depth)];
    start.x = s.x;
    start.v = s.v;
    const double e0 = total_energy(s);
    if (!step_implicit(s, report, h))
        return false;
    const double e1 = total_energy(s);
    // Work of the external forces (constant over the step; gravity is in the potential).
    double work = 0;
    if (m_fext.size() == 3 * s.x.rows()) {
        const auto x1 = flat(s.x);
        const auto x0 = flat(start.x);
        const auto& dof_map = m_model->dof_map();
        for (std::size_t k = 0; k < dof_map.size(); ++k)
            if (dof_map[k] != kNone)
                work += m_fext(Index(k)) * (x1(Index(k)) - x0(Index(k)));
    }
    const double scale = std::max({ std::abs(e0), std::abs(e1), std::abs(work), 1e-300 });
    if (e1 <= e0 + work + 1e-9 * scale)
        return true;
    if (depth >= m_options.max_energy_halvings) {
        // Smaller steps did not remove the gain, so it does not come from the step size alone
        // (the affine-fit rotation of hexes and polyhedra makes their corotated force slightly
        // non-conservative). Shorten the step instead: x = x0 + s (x1 - x0), v = s v1, with
        // the largest s in [0, 1] (bisection) whose energy does not exceed the start's plus
        // the work done; s = 0 (the tissue held where it was, at rest) always qualifies.
        const MatX3 x1 = s.x, v1 = s.v;
        auto energy_at = [&](double f, double& w_out) {
            s.x = start.x + f * (x1 - start.x);
            s.v = f * v1;
            w_out = f * work;
            return total_energy(s);
        };
        double lo = 0, hi = 1, w = 0;
        for (int k = 0; k < 12; ++k) {
            const double mid = 0.5 * (lo + hi);
            if (energy_at(mid, w) <= e0 + w + 1e-9 * scale)
                lo = mid;
            else
                hi = mid;
        }
        energy_at(lo, w);
        report.warnings.push_back("energy rose by " + std::to_string(e1 - e0 - work)
            + " J in a step of " + std::to_string(h) + " s after halving it "
            + std::to_string(depth) + " times; the step was shortened to " + std::to_string(lo)
            + " of it");
        return true;
    }
    // Redo as two half steps; the cached step matrix was made for h.
    s.x = start.x;
    s.v = start.v;
    m_stiffness_age = -1;
    ++report.substeps; // a step split in two adds one
    const bool ok = step_implicit_guarded(s, report, 0.5 * h, depth + 1)
        && step_implicit_guarded(s, report, 0.5 * h, depth + 1);
    m_stiffness_age = -1;
    return ok;
}

} // namespace polycut::integrate
