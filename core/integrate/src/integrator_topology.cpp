// The integrator across topology changes (a cut renumbered or added DOFs: matrices made again,
// the AMG hierarchy carried over, docs/decisions/0009 and 0017) and ahead of the first step
// (the hierarchy set up at load).
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/integrate/integrator.hpp"

#include <exception>

namespace polycut::integrate {

void Integrator::ensure_topology(StepReport& report) {
    if (m_model->topology_version() == m_topology)
        return;
    const std::uint64_t before = m_topology;
    m_topology = m_model->topology_version();
    // The new pattern in the matrices' own storage: fresh ones (and a copy of K for A) were
    // half of the step's topology update on the organ, most of it page faults and zero fills
    // (perf, bench_cut). Their values are written before use (assembly, scale_shift_multiply).
    // K only where a step assembles it (Integrator::assemble): with the step matrix from the
    // kernels (assemble_step_matrix) it is never formed, and its pattern is not copied.
    m_K_pattern_stale = true;
    m_model->pattern_into(m_A);
    // A cut that kept the node ids keeps the AMG hierarchy, carried over to the new DOF
    // numbering through the old dof map (issue 12 item 5: no blocking set-up per cut; the
    // lagged set-up rule sets up again when solves need it).
    bool kept = false;
    // A face snap that compacted the nodes renumbered them: the hierarchy follows the map.
    const std::vector<Index>* node_map = nullptr;
    if (!m_lagged && before != ~std::uint64_t(0)
        && (m_model->nodes_kept_since(before)
            || (node_map = m_model->node_map_since(before)) != nullptr)) {
        kept = m_solver.remap(row_remap(node_map));
    }
    m_dof_map_then = m_model->dof_map();
    if (!kept)
        m_solver.reset();
    m_solver.set_blocks(m_model->dof_blocks());
    if (m_solver.wants_coarse_space())
        m_solver.set_coarse_space(m_model->coarse_space());
    if (m_lagged) {
        // New pattern: the running job (if any) is for the old one. The next solve starts the
        // new factor in the background unless there never was a factor (the first solve
        // factors in the foreground, as at start-up).
        m_factor_job->cancel();
        m_handover_in = -1;
        m_lagged_status.pending = false;
        m_pattern_changed = m_pattern_changed || m_has_factor;
        m_has_factor = false;
    }
    m_dv.setZero(m_model->num_free_dofs());
    m_dv_prev.resize(0);
    m_stiffness_age = -1;
    m_model->rest_rows(m_rest);
    geometry::Aabb box;
    for (Index i = 0; i < m_rest.rows(); ++i)
        box.extend(m_rest.row(i).transpose());
    m_divergence_limit = m_options.divergence_factor * std::max(box.diagonal(), 1e-12);
    if (report.warnings.empty() && m_model->num_free_dofs() == 0)
        report.warnings.emplace_back("no free degrees of freedom");
}

solve::RowRemap Integrator::row_remap(const std::vector<Index>* node_map) const {
    const auto& now = m_model->dof_map();
    const std::size_t n = std::size_t(m_model->num_free_dofs());
    // full DOF now -> full DOF then (the same unless a node map renumbered the rows)
    std::vector<Index> then_row;
    if (node_map) {
        then_row.assign(now.size() / 3, kNone);
        for (std::size_t o = 0; o < node_map->size(); ++o) {
            const Index r = (*node_map)[o];
            if (r != kNone && std::size_t(r) < then_row.size())
                then_row[std::size_t(r)] = Index(o);
        }
    }
    solve::RowRemap m;
    m.old_of.assign(n, -1);
    std::vector<int> axis(n, 0);
    for (std::size_t k = 0; k < now.size(); ++k) {
        if (now[k] == kNone)
            continue;
        axis[std::size_t(now[k])] = int(k % 3);
        std::size_t then = k;
        if (node_map) {
            const Index row = then_row[k / 3];
            then = row == kNone ? m_dof_map_then.size() : 3 * std::size_t(row) + k % 3;
        }
        if (then < m_dof_map_then.size() && m_dof_map_then[then] != kNone)
            m.old_of[std::size_t(now[k])] = long(m_dof_map_then[then]);
    }
    // A node a cut duplicated or created interpolates the coarse space as the mean of its
    // surviving neighbours (same axis, through the new pattern): smooth fields on its side of
    // the cut stay in the coarse space (a zero row left such nodes to the smoother alone: PCG
    // needed up to 18 iterations instead of 4 during a live organ incision).
    m.origin_ptr.assign(n + 1, 0);
    for (std::size_t r = 0; r < n; ++r) {
        const int first = int(m.origin_row.size());
        if (m.old_of[r] < 0 && long(r) < m_A.outerSize())
            for (SparseMatrix::InnerIterator it(m_A, Eigen::Index(r)); it; ++it) {
                const auto j = std::size_t(it.index());
                if (j != r && m.old_of[j] >= 0 && axis[j] == axis[r])
                    m.origin_row.push_back(m.old_of[j]);
            }
        const int count = int(m.origin_row.size()) - first;
        for (int c = 0; c < count; ++c)
            m.origin_weight.push_back(1.0 / count);
        m.origin_ptr[r + 1] = int(m.origin_row.size());
    }
    return m;
}

bool Integrator::prepare(const State& s) {
    m_prepared_x.resize(0, 3);
    if (m_options.kind != IntegratorKind::ImplicitEuler || m_lagged || !m_solver.wants_prepare())
        return false;
    try {
        StepReport report;
        ensure_topology(report);
        if (s.x.rows() != m_model->num_rows() || m_model->num_free_dofs() == 0 || !s.x.allFinite()
            || s.v.rows() != s.x.rows())
            return false;
        // The first step's assembly, done here and kept for it (step_implicit() takes it when
        // it starts from these positions): assembling again would start the corotation's polar
        // iterations from these rotations and differ in round-off.
        // the same assembly as step_implicit() would make (bit for bit)
        const double h = m_options.dt;
        const double cK = h * m_model->material().rayleigh_stiffness + h * h;
        const double cM = 1.0 + h * m_model->material().rayleigh_mass;
        m_prepared_direct
            = m_options.stiffness_every <= 1 && cK > 0 && assemble_step_matrix(s, cK, cM, report);
        if (m_prepared_direct) {
            m_prepared_v = s.v;
            m_prepared_h = h;
        } else {
            assemble(s.x, m_options.force_mode, true, report);
            gather_free(s.v, m_v_r);
            m_shift = cM * m_model->reduced_mass();
            solve::scale_shift_multiply(m_K, cK, m_shift, m_v_r, m_A, m_tmp, m_model->threads());
        }
        m_prepared_x = s.x;
        m_prepared_cells = m_model->cell_version();
        pass_coordinates(s.x);
        return m_solver.prepare(m_A);
    } catch (const std::exception&) {
        m_prepared_x.resize(0, 3);
        return false; // the first step sets up (and reports) instead
    }
}

} // namespace polycut::integrate
