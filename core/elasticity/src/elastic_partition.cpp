// ElasticModel's partition of the cells for the threaded assembly: each thread takes the cells
// whose nodes all lie in its node range (so no two threads write the same node's rows or
// columns), the rest is assembled serially after them.
#include "polycut/common/error.hpp"
#include "polycut/elasticity/elastic_model.hpp"

#include <algorithm>
#include <numeric>
#include <span>

namespace polycut::elasticity {

void ElasticModel::rebuild_partition() {
    const std::size_t count = m_cells.size();
    if (m_node_offset.size() != count + 1)
        throw StateError("ElasticModel::rebuild_partition", "the pattern is not built");
    const int T = std::max(m_threads, 1);
    m_thread_cells.assign(std::size_t(T), {});
    m_shared_cells.clear();
    if (T == 1) {
        m_thread_cells[0].resize(count);
        std::iota(m_thread_cells[0].begin(), m_thread_cells[0].end(), Index(0));
        return;
    }
    // The flat cell -> nodes arrays of the pattern (the scattered CellData would cost a cache
    // miss per cell).
    const auto cell_nodes = [&](std::size_t c) {
        return std::span<const Index>(
            m_node_list.data() + m_node_offset[c], m_node_offset[c + 1] - m_node_offset[c]);
    };
    Index nodes = 0;
    for (Index i : m_node_list)
        nodes = std::max(nodes, i + 1);
    // The node ranges are those of the nodes the model was built with (m_partition_nodes): a
    // cut appends nodes at the end, and ranges over all ids would put every cell of the cut
    // (old nodes in any range, new ones in the last) into the serial part (its assembly went
    // from 4.4 to 8.8 ms over a stroke on the 5k organ). New nodes take the range of the cells
    // that made them instead.
    if (m_partition_nodes <= 0 || m_partition_nodes > nodes)
        m_partition_nodes = nodes;
    const Index base = m_partition_nodes;
    // Node ranges [bound[t], bound[t + 1]) holding ~count / T cells each, a cell counted at the
    // middle of its (old) node ids: a cell across a bound then counts on either side as often as
    // on the other, so each thread loses about as many cells to the serial part. (Counted at
    // their first node, every cell across a bound was taken from the range below it: on organ_5k
    // 11,575 / 13,187 tets for the two threads and 1,617 serial.)
    std::vector<long> per_node(std::size_t(base) + 1, 0);
    long counted = 0;
    for (std::size_t c = 0; c < count; ++c) {
        Index lo = base, hi = -1;
        for (Index i : cell_nodes(c))
            if (i < base) {
                lo = std::min(lo, i);
                hi = std::max(hi, i);
            }
        if (hi >= 0) {
            ++per_node[std::size_t(lo + (hi - lo) / 2)];
            ++counted;
        }
    }
    std::vector<Index> bound(std::size_t(T) + 1, base);
    bound.front() = 0;
    long seen = 0;
    int t = 1;
    for (Index i = 0; i < base && t < T; ++i) {
        seen += per_node[std::size_t(i)];
        while (t < T && seen * T >= counted * t)
            bound[std::size_t(t++)] = i + 1;
    }
    std::vector<int> owner(std::size_t(nodes), -1);
    for (Index i = 0; i < base; ++i)
        owner[std::size_t(i)]
            = int(std::upper_bound(bound.begin(), bound.end(), i) - bound.begin()) - 1;
    // A new node joins the range of the first cell (in cell order) that has an old node.
    for (std::size_t c = 0; c < count; ++c) {
        const auto n = cell_nodes(c);
        const auto old = std::min_element(n.begin(), n.end());
        if (old == n.end() || *old >= base)
            continue;
        for (Index i : n)
            if (owner[std::size_t(i)] < 0)
                owner[std::size_t(i)] = owner[std::size_t(*old)];
    }
    for (std::size_t c = 0; c < count; ++c) {
        const auto n = cell_nodes(c);
        if (n.empty())
            continue;
        const int a = owner[std::size_t(n.front())];
        if (a >= 0 && a < T
            && std::all_of(n.begin(), n.end(), [&](Index i) { return owner[std::size_t(i)] == a; }))
            m_thread_cells[std::size_t(a)].push_back(Index(c));
        else
            m_shared_cells.push_back(Index(c));
    }
}

} // namespace polycut::elasticity
