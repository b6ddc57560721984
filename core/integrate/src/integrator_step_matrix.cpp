// The implicit step's matrix straight from the model's kernels (decision 0073): A = cK K_R + cM
// M and K_R v without forming K (Model::assemble_step).
#include "polycut/common/stats.hpp"
#include "polycut/integrate/integrator.hpp"

namespace polycut::integrate {

bool Integrator::assemble_step_matrix(const State& s, double cK, double cM, StepReport& report) {
    const Stopwatch sw;
    // K_R v needs v zero at fixed DOFs (it is K_R restricted to the free ones times v_r)
    m_v_masked = s.v;
    const std::vector<Index>& dof_map = m_model->dof_map();
    double* v = m_v_masked.data();
    for (std::size_t k = 0; k < dof_map.size(); ++k)
        if (dof_map[k] == kNone)
            v[k] = 0;
    m_shift = cM * m_model->reduced_mass();
    if (!m_model->assemble_step(
            s.x, m_options.force_mode, cK, m_shift, m_v_masked, m_A, m_fint, m_full))
        return false;
    m_model->reduce(m_fint, m_fint_r);
    m_model->reduce(m_full, m_tmp);
    m_tmp /= cK; // K_R v_r, as scale_shift_multiply() gives it
    report.assembly_ms += sw.ms();
    return true;
}

} // namespace polycut::integrate
