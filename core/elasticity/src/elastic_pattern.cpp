// ElasticModel::rebuild_pattern: the DOF numbering, the CSC pattern of the reduced stiffness and
// the cells' scatter maps into it, built per node (a cut rebuilds them, so this must cost
// milliseconds on an organ).
#include "polycut/elasticity/elastic_model.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>

namespace polycut::elasticity {

void ElasticModel::rebuild_pattern() {
    const std::size_t ndof = 3 * std::size_t(m_mesh->num_nodes());
    // DOFs of nodes that no cell uses are eliminated too (they would be singular).
    std::vector<std::uint8_t> used(std::size_t(m_mesh->num_nodes()), 0);
    for (const CellData& cd : m_cells)
        for (Index i : cd.nodes)
            used[std::size_t(i)] = 1;
    m_dof_map.assign(ndof, kNone);
    m_free_dofs.clear();
    for (std::size_t k = 0; k < ndof; ++k)
        if (!m_fixed[k] && used[k / 3]) {
            m_dof_map[k] = Index(m_free_dofs.size());
            m_free_dofs.push_back(Index(k));
        }
    m_num_free = Index(m_free_dofs.size());

    // The pattern is built per node, not per DOF: the rows of the three columns of node j are
    // the free DOFs of the nodes sharing a cell with j (its neighbours, j included), in node
    // order, which is DOF order. A cut rebuilds it, so it must cost a few milliseconds on an
    // organ, not the ~100 ms of sorting 144 entries per tet into per-DOF columns.
    const std::size_t nn = std::size_t(m_mesh->num_nodes());
    std::vector<std::size_t> cell_offset(nn + 1, 0); // node -> cells, CSR
    for (const CellData& cd : m_cells)
        for (Index i : cd.nodes)
            ++cell_offset[std::size_t(i) + 1];
    std::partial_sum(cell_offset.begin(), cell_offset.end(), cell_offset.begin());
    std::vector<Index> cells_of(cell_offset[nn]);
    {
        std::vector<std::size_t> fill(nn);
        std::copy_n(cell_offset.begin(), nn, fill.begin());
        for (std::size_t c = 0; c < m_cells.size(); ++c)
            for (Index i : m_cells[c].nodes)
                cells_of[fill[std::size_t(i)]++] = Index(c);
    }
    // Free axes of each node: count, and the rank of each free axis among them.
    std::vector<std::uint8_t> free_count(nn, 0);
    std::vector<std::array<std::uint8_t, 3>> axis_rank(nn);
    for (std::size_t i = 0; i < nn; ++i)
        for (std::size_t a = 0; a < 3; ++a) {
            axis_rank[i][a] = free_count[i];
            free_count[i] += m_dof_map[3 * i + a] != kNone ? 1 : 0;
        }
    // Neighbours of each node (sorted, unique) and where each one's rows start in its columns.
    m_nb_offset.assign(nn + 1, 0);
    m_nb_nodes.clear();
    m_nb_start.clear();
    m_nb_length.assign(nn, 0);
    std::vector<Index> buffer;
    std::vector<std::size_t> stamp(nn, std::numeric_limits<std::size_t>::max());
    for (std::size_t j = 0; j < nn; ++j) {
        buffer.clear();
        for (std::size_t k = cell_offset[j]; k < cell_offset[j + 1]; ++k)
            for (Index i : m_cells[std::size_t(cells_of[k])].nodes)
                if (stamp[std::size_t(i)] != j) {
                    stamp[std::size_t(i)] = j;
                    buffer.push_back(i);
                }
        std::sort(buffer.begin(), buffer.end());
        int start = 0;
        for (Index i : buffer) {
            m_nb_nodes.push_back(i);
            m_nb_start.push_back(start);
            start += free_count[std::size_t(i)];
        }
        m_nb_length[j] = start;
        m_nb_offset[j + 1] = m_nb_nodes.size();
    }
    m_outer.assign(std::size_t(m_num_free) + 1, 0);
    for (Index c = 0; c < m_num_free; ++c)
        m_outer[std::size_t(c) + 1]
            = m_outer[std::size_t(c)] + m_nb_length[std::size_t(m_free_dofs[std::size_t(c)]) / 3];
    m_inner.resize(std::size_t(m_outer[std::size_t(m_num_free)]));
    for (Index c = 0; c < m_num_free; ++c) {
        const std::size_t j = std::size_t(m_free_dofs[std::size_t(c)]) / 3;
        int* out = m_inner.data() + m_outer[std::size_t(c)];
        for (std::size_t k = m_nb_offset[j]; k < m_nb_offset[j + 1]; ++k) {
            const std::size_t i = std::size_t(m_nb_nodes[k]);
            for (std::size_t a = 0; a < 3; ++a)
                if (const Index r = m_dof_map[3 * i + a]; r != kNone)
                    *out++ = int(r);
        }
    }
    // Offset of the rows of node i within each column of node j (i a neighbour of j).
    auto row_offset = [&](std::size_t i, std::size_t j) {
        const auto first = m_nb_nodes.begin() + std::ptrdiff_t(m_nb_offset[j]);
        const auto last = m_nb_nodes.begin() + std::ptrdiff_t(m_nb_offset[j + 1]);
        const std::size_t k = std::size_t(std::lower_bound(first, last, Index(i)) - first);
        return m_nb_start[m_nb_offset[j] + k];
    };
    m_diag_slots.resize(std::size_t(m_num_free));
    for (Index r = 0; r < m_num_free; ++r) {
        const std::size_t k = std::size_t(m_free_dofs[std::size_t(r)]), i = k / 3;
        m_diag_slots[std::size_t(r)]
            = m_outer[std::size_t(r)] + row_offset(i, i) + axis_rank[i][k % 3];
    }
    // Compact scatter of the P1 tets whose 12 DOFs are free (the batched kernel's fast path):
    // block (i, j) lies at slot(3i, 3j) + b L_j + a (a node's rows are consecutive in a column,
    // its three columns share their rows; L_j is the column length of node j).
    const auto all_free = [&](std::size_t i) { return free_count[i] == 3; };
    std::vector<char> compact(m_cells.size(), 0);
    m_block_scatter.assign(20 * m_cells.size(), -1);
    for (std::size_t c = 0; c < m_cells.size(); ++c) {
        const auto& nodes = m_cells[c].nodes;
        if (nodes.size() != 4 || !m_p1[c].valid
            || !std::all_of(
                nodes.begin(), nodes.end(), [&](Index i) { return all_free(std::size_t(i)); }))
            continue;
        compact[c] = 1;
        int* blk = m_block_scatter.data() + 20 * c;
        for (std::size_t j = 0; j < 4; ++j) {
            const std::size_t nj = std::size_t(nodes[j]);
            blk[16 + j] = m_nb_length[nj];
            const int col = m_outer[std::size_t(m_dof_map[3 * nj])];
            for (std::size_t i = 0; i < 4; ++i)
                blk[4 * i + j] = col + row_offset(std::size_t(nodes[i]), nj);
        }
    }
    // Full scatter of the other cells: entry (row 3i+a, col 3j+b) of the cell matrix -> value
    // slot (-1: a fixed DOF).
    m_scatter_offset.assign(m_cells.size() + 1, 0);
    for (std::size_t c = 0; c < m_cells.size(); ++c) {
        const std::size_t d = compact[c] ? 0 : 3 * m_cells[c].nodes.size();
        m_scatter_offset[c + 1] = m_scatter_offset[c] + d * d;
    }
    m_scatter.assign(m_scatter_offset[m_cells.size()], -1);
    // Column by column of node j: the rows' offsets of j's neighbours from a position map, then
    // every cell of j fills the block column of j (no search per node pair).
    std::vector<int> offset_of(nn, -1);
    for (std::size_t j = 0; j < nn; ++j) {
        if (free_count[j] == 0)
            continue;
        for (std::size_t k = m_nb_offset[j]; k < m_nb_offset[j + 1]; ++k)
            offset_of[std::size_t(m_nb_nodes[k])] = m_nb_start[k];
        for (std::size_t k = cell_offset[j]; k < cell_offset[j + 1]; ++k) {
            const std::size_t c = std::size_t(cells_of[k]);
            if (compact[c])
                continue;
            const auto& nodes = m_cells[c].nodes;
            const std::size_t n = nodes.size(), d = 3 * n;
            const std::size_t q
                = std::size_t(std::find(nodes.begin(), nodes.end(), Index(j)) - nodes.begin());
            int* sc = m_scatter.data() + m_scatter_offset[c];
            for (std::size_t p = 0; p < n; ++p) {
                const std::size_t i = std::size_t(nodes[p]);
                if (free_count[i] == 0)
                    continue;
                const int off = offset_of[i];
                for (std::size_t b = 0; b < 3; ++b) {
                    const Index col = m_dof_map[3 * j + b];
                    if (col == kNone)
                        continue;
                    for (std::size_t a = 0; a < 3; ++a)
                        if (m_dof_map[3 * i + a] != kNone)
                            sc[(3 * p + a) * d + 3 * q + b]
                                = m_outer[std::size_t(col)] + off + axis_rank[i][a];
                }
            }
        }
    }
    m_node_offset.assign(m_cells.size() + 1, 0);
    m_node_list.clear();
    for (std::size_t c = 0; c < m_cells.size(); ++c) {
        m_node_list.insert(m_node_list.end(), m_cells[c].nodes.begin(), m_cells[c].nodes.end());
        m_node_offset[c + 1] = m_node_list.size();
    }
    rebuild_partition();
    ++m_topology_version;
}

} // namespace polycut::elasticity
