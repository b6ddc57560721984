// ElasticModel's lumped masses: the nodal masses summed over the cells (rebuild_mass), the same
// for the nodes a cut affected only (update_mass, bit-identical: issue 12 item 5, decision 0016),
// and the per-DOF inertia gathered from them when a dynamic step asks (reduced_mass).
#include "polycut/common/error.hpp"
#include "polycut/elasticity/elastic_model.hpp"

#include <cstdlib>

namespace polycut::elasticity {

const VecX& ElasticModel::reduced_mass() const {
    if (m_reduced_mass_stale) {
        m_reduced_mass.resize(m_num_free);
        for (Index r = 0; r < m_num_free; ++r)
            m_reduced_mass(r) = m_mass(m_free_dofs[std::size_t(r)] / 3);
        m_reduced_mass_stale = false;
        m_inertia_built = true;
    }
    return m_reduced_mass;
}

void ElasticModel::rebuild_mass() {
    ++m_cell_version; // every change of cells or fixed DOFs ends here
    m_mass.setZero(m_mesh->num_nodes());
    for (const CellData& cd : m_cells)
        for (std::size_t i = 0; i < cd.nodes.size(); ++i)
            m_mass(cd.nodes[i]) += m_material.density * cd.integration.lumped_volume(Index(i));
    m_reduced_mass_stale = true; // reduced_mass() gathers it when a dynamic step asks
    if (m_nodal)
        refresh_nodal();
}

void ElasticModel::update_mass(const std::vector<char>& affected) {
    const Index nn = m_mesh->num_nodes();
    if (affected.size() != std::size_t(nn) || m_node_offset.size() != m_cells.size() + 1
        || m_nodal) {
        rebuild_mass();
        return;
    }
    ++m_cell_version;
    const Index old = Index(m_mass.size()); // more than nn after an undo dropped nodes
    m_mass.conservativeResize(nn);
    for (Index n = old; n < nn; ++n)
        m_mass(n) = 0;
    for (Index n = 0; n < nn; ++n)
        if (affected[std::size_t(n)])
            m_mass(n) = 0;
    for (std::size_t c = 0; c < m_cells.size(); ++c) {
        const std::size_t begin = m_node_offset[c], end = m_node_offset[c + 1];
        bool any = false;
        for (std::size_t k = begin; k < end && !any; ++k)
            any = affected[std::size_t(m_node_list[k])] != 0;
        if (!any)
            continue;
        const CellData& cd = m_cells[c];
        for (std::size_t i = 0; i < cd.nodes.size(); ++i)
            if (affected[std::size_t(cd.nodes[i])])
                m_mass(cd.nodes[i]) += m_material.density * cd.integration.lumped_volume(Index(i));
    }
    m_reduced_mass_stale = true; // reduced_mass() gathers it when a dynamic step asks
    if (const char* v = std::getenv("POLYCUT_CHECK_UNDO"); v != nullptr && v[0] == '1') {
        const auto partial = m_mass;
        rebuild_mass();
        if (partial != m_mass)
            throw StateError("ElasticModel::update_mass",
                "the masses of the affected nodes differ from a full rebuild");
    }
}

} // namespace polycut::elasticity
