// ElasticModel's pattern: the DOF numbering, the CSC pattern of the reduced stiffness and the
// cells' scatter maps into it, built per node. After a cut only the nodes whose cells changed
// get new neighbour lists and columns, only the cells around them new scatter maps; the rest is
// copied with its value slots shifted (issue 12 item 5: the cut's cost follows what it touched;
// a full build of the 5k-node organ cost ~20 ms per cut).
#include "polycut/elasticity/elastic_model.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <span>
#include <utility>

namespace polycut::elasticity {

void ElasticModel::rebuild_pattern() {
    build_pattern({}, {});
}

void ElasticModel::build_pattern(std::vector<char> affected, std::vector<Index> old_cell) {
    const std::size_t nn = std::size_t(m_mesh->num_nodes());
    const std::size_t n_cells = m_cells.size();
    const std::size_t n_old = m_nb_offset.empty() ? 0 : m_nb_offset.size() - 1;
    if (old_cell.size() != n_cells || m_node_offset.empty())
        old_cell.assign(n_cells, kNone);
    // The cells' nodes as one flat array (CSR): every pass below reads it, not the scattered
    // CellData (a cache miss per cell on a 27k-cell organ); the same cells' copied.
    const std::vector<std::size_t> old_node_offset = std::move(m_node_offset);
    const std::vector<Index> old_node_list = std::move(m_node_list);
    m_node_offset.assign(n_cells + 1, 0);
    for (std::size_t c = 0; c < n_cells; ++c) {
        const std::size_t o = std::size_t(old_cell[c]);
        m_node_offset[c + 1] = m_node_offset[c]
            + (old_cell[c] != kNone ? old_node_offset[o + 1] - old_node_offset[o]
                                    : m_cells[c].nodes.size());
    }
    m_node_list.resize(m_node_offset[n_cells]);
    for (std::size_t c = 0; c < n_cells; ++c) {
        const auto to = m_node_list.begin() + std::ptrdiff_t(m_node_offset[c]);
        if (const Index o = old_cell[c]; o != kNone)
            std::copy(old_node_list.begin() + std::ptrdiff_t(old_node_offset[std::size_t(o)]),
                old_node_list.begin() + std::ptrdiff_t(old_node_offset[std::size_t(o) + 1]), to);
        else
            std::copy(m_cells[c].nodes.begin(), m_cells[c].nodes.end(), to);
    }
    const auto cell_nodes = [&](std::size_t c) {
        return std::span<const Index>(
            m_node_list.data() + m_node_offset[c], m_node_offset[c + 1] - m_node_offset[c]);
    };
    // DOFs of nodes that no cell uses are eliminated too (they would be singular).
    std::vector<std::uint8_t> used(nn, 0);
    for (Index i : m_node_list)
        used[std::size_t(i)] = 1;
    // Incremental when node ids were kept (appended nodes count as affected; nodes dropped from
    // the end, an undo's, leave affected every node they were a neighbour of) and the fixed DOFs
    // of the other nodes too (update_cells() keeps their mask): an unaffected node then has the
    // same cells, neighbours and free axes as before.
    const bool incremental
        = affected.size() == nn && old_cell.size() == n_cells && m_dof_map.size() == 3 * n_old;
    for (std::size_t j = n_old; incremental && j < nn; ++j)
        affected[j] = 1;
    if (!incremental) {
        affected.assign(nn, 1);
        old_cell.assign(n_cells, kNone);
    }
    // VolumetricRule::NodalAverage couples the nodes of each node's patch: neighbours are two
    // rings apart. A node's two-ring changes when a node of its one-ring had its cells changed,
    // so the affected set grows by one ring (nodal_dilatation.hpp).
    const bool two_ring = m_nodal != nullptr;
    if (two_ring && incremental) {
        std::vector<char> grown(affected);
        for (std::size_t c = 0; c < n_cells; ++c) {
            const auto nodes = cell_nodes(c);
            if (std::any_of(nodes.begin(), nodes.end(),
                    [&](Index i) { return affected[std::size_t(i)] != 0; }))
                for (Index i : nodes)
                    grown[std::size_t(i)] = 1;
        }
        affected = std::move(grown);
    }
    // The old arrays are read below while the new ones are written: the largest new ones take
    // the storage the previous update left (m_spare) and give theirs back at the end.
    const std::vector<std::size_t> old_nb_offset = std::move(m_nb_offset);
    std::vector<Index> old_nb_nodes = std::exchange(m_nb_nodes, std::move(m_spare.nb_nodes));
    std::vector<int> old_nb_start = std::exchange(m_nb_start, std::move(m_spare.nb_start));
    const std::vector<int> old_outer = std::move(m_outer);
    std::vector<int> old_inner = std::exchange(m_inner, std::move(m_spare.inner));
    const std::vector<Index> old_diag = std::move(m_diag_slots);
    std::vector<int> old_block = std::exchange(m_block_scatter, std::move(m_spare.block_scatter));
    const std::vector<std::size_t> old_scatter_offset = std::move(m_scatter_offset);
    std::vector<int> old_scatter = std::exchange(m_scatter, std::move(m_spare.scatter));
    const std::vector<Index> old_dof_map = std::move(m_dof_map);
    const Index old_num_free = m_num_free;

    // DOF numbering. A node a cut left without cells (a crack-front node taken out of the faces)
    // loses its DOFs and the later ones move down: new_of_old maps the old reduced DOFs.
    m_dof_map.assign(3 * nn, kNone);
    m_free_dofs.clear();
    for (std::size_t k = 0; k < 3 * nn; ++k)
        if (!m_fixed[k] && used[k / 3]) {
            m_dof_map[k] = Index(m_free_dofs.size());
            m_free_dofs.push_back(Index(k));
        }
    m_num_free = Index(m_free_dofs.size());
    std::vector<Index> new_of_old;
    bool same_numbering = true;
    if (incremental) {
        new_of_old.assign(std::size_t(old_num_free), kNone);
        for (std::size_t k = 0; k < old_dof_map.size(); ++k)
            if (const Index r = old_dof_map[k]; r != kNone) {
                // a dropped node's DOFs (k past the end) are in no unaffected node's column
                const Index now = k < m_dof_map.size() ? m_dof_map[k] : kNone;
                new_of_old[std::size_t(r)] = now;
                same_numbering = same_numbering && (now == r || k >= m_dof_map.size());
            }
    }

    // Cells of the affected nodes (CSR).
    std::vector<std::size_t> cell_offset(nn + 1, 0);
    for (Index i : m_node_list)
        if (two_ring || affected[std::size_t(i)])
            ++cell_offset[std::size_t(i) + 1];
    std::partial_sum(cell_offset.begin(), cell_offset.end(), cell_offset.begin());
    std::vector<Index> cells_of(cell_offset[nn]);
    {
        std::vector<std::size_t> fill(cell_offset.begin(), cell_offset.end() - 1);
        for (std::size_t c = 0; c < n_cells; ++c)
            for (Index i : cell_nodes(c))
                if (two_ring || affected[std::size_t(i)])
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
    // Neighbours of each node (sorted, unique; the node itself included) and where each one's
    // rows start in the node's columns. The rows of the three columns of node j are the free
    // DOFs of its neighbours, in node order, which is DOF order.
    m_nb_offset.assign(nn + 1, 0);
    m_nb_nodes.clear();
    m_nb_nodes.reserve(old_nb_nodes.size() + 64 * (nn > n_old ? nn - n_old : 0));
    m_nb_start.clear();
    m_nb_start.reserve(m_nb_nodes.capacity());
    m_nb_length.resize(nn, 0);
    std::vector<Index> buffer;
    std::vector<std::size_t> stamp(nn, std::numeric_limits<std::size_t>::max());
    for (std::size_t j = 0; j < nn; ++j) {
        if (!affected[j]) {
            const auto b = std::ptrdiff_t(old_nb_offset[j]),
                       e = std::ptrdiff_t(old_nb_offset[j + 1]);
            m_nb_nodes.insert(m_nb_nodes.end(), old_nb_nodes.begin() + b, old_nb_nodes.begin() + e);
            m_nb_start.insert(m_nb_start.end(), old_nb_start.begin() + b, old_nb_start.begin() + e);
        } else {
            buffer.clear();
            const auto add_cells_of = [&](std::size_t a) {
                for (std::size_t k = cell_offset[a]; k < cell_offset[a + 1]; ++k)
                    for (Index i : cell_nodes(std::size_t(cells_of[k])))
                        if (stamp[std::size_t(i)] != j) {
                            stamp[std::size_t(i)] = j;
                            buffer.push_back(i);
                        }
            };
            add_cells_of(j);
            if (two_ring)
                for (std::size_t r = 0, ring = buffer.size(); r < ring; ++r)
                    add_cells_of(std::size_t(buffer[r]));
            std::sort(buffer.begin(), buffer.end());
            int start = 0;
            for (Index i : buffer) {
                m_nb_nodes.push_back(i);
                m_nb_start.push_back(start);
                start += free_count[std::size_t(i)];
            }
            m_nb_length[j] = start;
        }
        m_nb_offset[j + 1] = m_nb_nodes.size();
    }
    // Columns: an unaffected node's are copied and its value slots shift by delta[j].
    m_outer.assign(std::size_t(m_num_free) + 1, 0);
    for (Index c = 0; c < m_num_free; ++c)
        m_outer[std::size_t(c) + 1]
            = m_outer[std::size_t(c)] + m_nb_length[std::size_t(m_free_dofs[std::size_t(c)]) / 3];
    m_inner.resize(std::size_t(m_outer[std::size_t(m_num_free)]));
    // delta[j] first (every column of node j shifts alike), then the columns on the model's
    // threads: each writes its own range of m_inner (these O(nnz) copies, and the two scatter
    // copies below, were ~2.8 ms of a 4.6 ms pattern update per cut on the split organ)
    std::vector<int> delta(nn, 0);
    for (Index c = 0; c < m_num_free; ++c) {
        const std::size_t k = std::size_t(m_free_dofs[std::size_t(c)]), j = k / 3;
        if (!affected[j])
            delta[j] = m_outer[std::size_t(c)] - old_outer[std::size_t(old_dof_map[k])];
    }
    const int threads = std::max(m_threads, 1);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (Index c = 0; c < m_num_free; ++c) {
        const std::size_t k = std::size_t(m_free_dofs[std::size_t(c)]), j = k / 3;
        int* out = m_inner.data() + m_outer[std::size_t(c)];
        if (!affected[j]) {
            const std::size_t o = std::size_t(old_dof_map[k]); // the same column before
            const auto from = old_inner.begin() + old_outer[o],
                       to = old_inner.begin() + old_outer[o + 1];
            if (same_numbering)
                std::copy(from, to, out);
            else
                std::transform(
                    from, to, out, [&](int r) { return int(new_of_old[std::size_t(r)]); });
            continue;
        }
        for (std::size_t q = m_nb_offset[j]; q < m_nb_offset[j + 1]; ++q) {
            const std::size_t i = std::size_t(m_nb_nodes[q]);
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
        m_diag_slots[std::size_t(r)] = !affected[i]
            ? old_diag[std::size_t(old_dof_map[k])] + delta[i]
            : m_outer[std::size_t(r)] + row_offset(i, i) + axis_rank[i][k % 3];
    }
    // A cell's maps are copied (slots shifted by their column node's delta) when it is the same
    // cell as before (old_cell) and none of its nodes is affected; else built.
    std::vector<Index> reuse(n_cells, kNone);
    for (std::size_t c = 0; c < n_cells; ++c) {
        const auto nodes = cell_nodes(c);
        if (old_cell[c] != kNone && std::none_of(nodes.begin(), nodes.end(), [&](Index i) {
                return affected[std::size_t(i)] != 0;
            }))
            reuse[c] = old_cell[c];
    }
    // Compact scatter of the P1 tets whose 12 DOFs are free (the batched kernel's fast path):
    // block (i, j) lies at slot(3i, 3j) + b L_j + a (a node's rows are consecutive in a column,
    // its three columns share their rows; L_j is the column length of node j).
    // Every entry is written below (-1 for the cells that are not compact): no fill first. A
    // reused cell is compact as it was (the same cell, its nodes' free axes unchanged), which
    // old_block says without touching the cell's P1 data (a cache miss per cell: this loop was
    // ~1.1 ms of a 3.9 ms pattern update per cut on the split organ).
    const auto all_free = [&](Index i) { return free_count[std::size_t(i)] == 3; };
    std::vector<char> compact(n_cells, 0);
    m_block_scatter.resize(20 * n_cells);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (std::size_t c = 0; c < n_cells; ++c) {
        const auto nodes = cell_nodes(c);
        int* blk = m_block_scatter.data() + 20 * c;
        if (const Index o = reuse[c]; o != kNone) {
            const int* from = old_block.data() + 20 * std::size_t(o);
            if (from[0] < 0) {
                std::fill(blk, blk + 20, -1);
                continue;
            }
            compact[c] = 1;
            const int shift4[4] = { delta[std::size_t(nodes[0])], delta[std::size_t(nodes[1])],
                delta[std::size_t(nodes[2])], delta[std::size_t(nodes[3])] };
            for (std::size_t e = 0; e < 16; ++e)
                blk[e] = from[e] + shift4[e % 4];
            std::copy(from + 16, from + 20, blk + 16);
            continue;
        }
        if (nodes.size() != 4 || !m_p1[c].valid
            || !std::all_of(nodes.begin(), nodes.end(), all_free)) {
            std::fill(blk, blk + 20, -1);
            continue;
        }
        compact[c] = 1;
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
    m_scatter_offset.assign(n_cells + 1, 0);
    for (std::size_t c = 0; c < n_cells; ++c) {
        const std::size_t d = compact[c] ? 0 : 3 * cell_nodes(c).size();
        m_scatter_offset[c + 1] = m_scatter_offset[c] + d * d;
    }
    m_scatter.resize(m_scatter_offset[n_cells]); // every entry written below
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256) if (threads > 1)
    for (std::size_t c = 0; c < n_cells; ++c) {
        if (compact[c])
            continue;
        thread_local std::vector<int> shift;
        const auto nodes = cell_nodes(c);
        const std::size_t n = nodes.size(), d = 3 * n;
        int* sc = m_scatter.data() + m_scatter_offset[c];
        if (const Index o = reuse[c]; o != kNone) {
            // entry (row, col) shifts by its column node's delta: one lookup per column, not
            // a division and a lookup per entry (this copy was ~35 % of a cut's pattern update)
            const int* from = old_scatter.data() + old_scatter_offset[std::size_t(o)];
            shift.resize(d);
            bool none = true;
            for (std::size_t q = 0; q < d; ++q) {
                shift[q] = delta[std::size_t(nodes[q / 3])];
                none = none && shift[q] == 0;
            }
            if (none) {
                std::copy(from, from + d * d, sc);
                continue;
            }
            for (std::size_t row = 0; row < d; ++row, from += d, sc += d)
                for (std::size_t q = 0; q < d; ++q)
                    sc[q] = from[q] < 0 ? from[q] : from[q] + shift[q];
            continue;
        }
        std::fill(sc, sc + d * d, -1); // the fixed DOFs' entries stay -1
        for (std::size_t q = 0; q < n; ++q) {
            const std::size_t j = std::size_t(nodes[q]);
            if (free_count[j] == 0)
                continue;
            for (std::size_t p = 0; p < n; ++p) {
                const std::size_t i = std::size_t(nodes[p]);
                if (free_count[i] == 0)
                    continue;
                const int off = row_offset(i, j);
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
    m_spare = { std::move(old_inner), std::move(old_scatter), std::move(old_block),
        std::move(old_nb_start), std::move(old_nb_nodes) };
    rebuild_partition();
    ++m_topology_version;
}

SparseMatrix ElasticModel::make_matrix() const {
    SparseMatrix A(m_num_free, m_num_free);
    A.resizeNonZeros(Index(m_inner.size()));
    std::copy(m_outer.begin(), m_outer.end(), A.outerIndexPtr());
    std::copy(m_inner.begin(), m_inner.end(), A.innerIndexPtr());
    std::fill(A.valuePtr(), A.valuePtr() + m_inner.size(), 0.0);
    return A;
}

void ElasticModel::pattern_into(SparseMatrix& M) const {
    if (M.rows() != m_num_free || M.cols() != m_num_free || !M.isCompressed())
        M.resize(m_num_free, m_num_free); // keeps the index and value storage
    M.data().resize(Index(m_inner.size()), 0.1);
    std::copy(m_outer.begin(), m_outer.end(), M.outerIndexPtr());
    std::copy(m_inner.begin(), m_inner.end(), M.innerIndexPtr());
}

} // namespace polycut::elasticity
