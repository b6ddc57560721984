// The implicit step's matrix straight from the model's kernels (decision 0073): A = cK K_R + cM
// M and K_R v without forming K (Model::assemble_step), and the diagonal slots the mass goes
// into.
#include "polycut/common/stats.hpp"
#include "polycut/integrate/integrator.hpp"

#include <algorithm>
#include <stdexcept>

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
    if (!m_model->assemble_step(s.x, m_options.force_mode, cK, m_v_masked, m_A, m_fint, m_full))
        return false;
    m_model->reduce(m_fint, m_fint_r);
    m_model->reduce(m_full, m_tmp);
    m_tmp /= cK; // K_R v_r, as scale_shift_multiply() gives it
    m_shift = cM * m_model->reduced_mass();
    add_to_diagonal_slots(m_A, m_shift);
    report.assembly_ms += sw.ms();
    return true;
}

void Integrator::add_to_diagonal_slots(solve::SparseMatrix& A, const VecX& d) {
    const Index n = A.cols();
    if (m_diagonal_slot.size() != std::size_t(n) || m_diagonal_nonzeros != A.nonZeros()
        || m_diagonal_cells != m_model->cell_version() || m_diagonal_outer != A.outerIndexPtr()) {
        m_diagonal_slot.resize(std::size_t(n));
        const int* outer = A.outerIndexPtr();
        const int* inner = A.innerIndexPtr();
        const int* counts = A.innerNonZeroPtr();
        for (Index j = 0; j < n; ++j) {
            const int* first = inner + outer[j];
            const int* last = first + (counts ? counts[j] : outer[j + 1] - outer[j]);
            const int* at = std::lower_bound(first, last, int(j));
            if (at == last || *at != int(j))
                throw std::logic_error("add_to_diagonal_slots: diagonal entry not stored");
            m_diagonal_slot[std::size_t(j)] = int(at - inner);
        }
        m_diagonal_nonzeros = A.nonZeros();
        m_diagonal_cells = m_model->cell_version();
        m_diagonal_outer = A.outerIndexPtr();
    }
    double* values = A.valuePtr();
    for (Index j = 0; j < n; ++j)
        values[m_diagonal_slot[std::size_t(j)]] += d(j);
}

} // namespace polycut::integrate
