// The integrator's side of penalty forces (penalty.hpp, issue 15 item 1): evaluation inside
// the step, the static tangent, and the per-node solve of semi-implicit Euler.
#include "polycut/integrate/integrator.hpp"

#include <Eigen/Dense>

namespace polycut::integrate {

bool Integrator::evaluate_penalty(const MatX3& x, const MatX3& v, double h, StepReport& report) {
    m_penalty_set.clear();
    if (!m_penalty)
        return false;
    m_penalty->evaluate(x, v, h, m_penalty_set);
    report.penalty_points = int(m_penalty_set.points.size());
    return !m_penalty_set.points.empty();
}

void Integrator::static_penalty(const State& s, StepReport& report) {
    if (!evaluate_penalty(s.x, s.v, 0.0, report))
        return;
    // K is assembled afresh at every Newton iteration: nothing to undo later.
    add_penalty_forces(m_penalty_set, nullptr, 0.0, m_model->dof_map(), 1.0, m_rhs);
    m_penalty_scratch.clear();
    report.penalty_entries_dropped += int(
        add_penalty_blocks(m_penalty_set, m_model->dof_map(), 1.0, 0.0, m_K, m_penalty_scratch));
}

void Integrator::semi_implicit_penalty_velocity(const State& s, double h, const VecX& M) {
    // dv form of (M + h^2 K_s) v' = M v + h (f + f_s): (M + h^2 K_s) dv = h (f + f_s - h K_s v),
    // with the penalty's h (f0 - h K v - D (v - v_other)) on the right and h^2 K + h D per node
    // on the left (cross-node coupling of embedded points dropped: semi-implicit Euler solves
    // per node).
    const std::vector<Index>& dof_map = m_model->dof_map();
    const Index n = m_model->num_rows();
    m_tmp = h * (m_rhs + m_spring_f - h * m_spring_diag.cwiseProduct(m_v_r));
    add_penalty_forces(m_penalty_set, &s.v, h, dof_map, h, m_tmp);
    penalty_node_blocks(m_penalty_set, n, h * h, h, m_node_blocks);
    const VecX diag = M + h * h * m_spring_diag;
    VecX dv = m_tmp.cwiseQuotient(diag);
    for (Index i = 0; i < n; ++i) {
        const Mat3& B = m_node_blocks[std::size_t(i)];
        if (B.isZero(0))
            continue;
        Eigen::Vector3i r;
        bool all_free = true;
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * std::size_t(i) + std::size_t(c);
            r[c] = k < dof_map.size() ? dof_map[k] : kNone;
            all_free = all_free && r[c] != kNone;
        }
        if (all_free) {
            Mat3 A = B;
            Vec3 b;
            for (int c = 0; c < 3; ++c) {
                A(c, c) += diag(r[c]);
                b(c) = m_tmp(r[c]);
            }
            const Vec3 x = A.ldlt().solve(b);
            for (int c = 0; c < 3; ++c)
                dv(r[c]) = x(c);
        } else {
            for (int c = 0; c < 3; ++c)
                if (r[c] != kNone)
                    dv(r[c]) = m_tmp(r[c]) / (diag(r[c]) + B(c, c));
        }
    }
    m_v_r += dv;
}

} // namespace polycut::integrate
