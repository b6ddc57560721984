// ElasticModel's partition of the cells for the threaded assembly: each thread takes the cells
// whose nodes all lie in its node range (so no two threads write the same node's rows or
// columns); with two threads most of the rest run in two groups on either side of a split of
// their band of nodes, and only the cells across that split are assembled serially.
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
    split_shared_cells();
}

void ElasticModel::split_shared_cells() {
    m_shared_groups.clear();
    // Two threads only: their shared cells lie along one band of nodes around the bound. Split
    // the band's nodes at the median of their rest positions along its longest extent; the
    // shared cells on one side each run on their own thread, the few across the median stay
    // serial (organ_20k: the 3,865 shared tets took 0.8 ms of a ~11 ms assembly, serially).
    constexpr std::size_t kMinShared = 256; // below this the second parallel region costs more
    if (m_thread_cells.size() != 2 || m_shared_cells.size() < kMinShared)
        return;
    const std::vector<Vec3>& rest = m_mesh->rest;
    std::vector<Index> band;
    for (const Index c : m_shared_cells)
        for (std::size_t k = m_node_offset[std::size_t(c)]; k < m_node_offset[std::size_t(c) + 1];
             ++k)
            band.push_back(m_node_list[k]);
    std::sort(band.begin(), band.end());
    band.erase(std::unique(band.begin(), band.end()), band.end());
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Index i : band) {
        lo = lo.cwiseMin(rest[std::size_t(i)]);
        hi = hi.cwiseMax(rest[std::size_t(i)]);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    std::vector<double> coordinate(band.size());
    for (std::size_t k = 0; k < band.size(); ++k)
        coordinate[k] = rest[std::size_t(band[k])](axis);
    std::vector<double> sorted = coordinate;
    std::nth_element(
        sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const auto side = [&](Index i) {
        const std::size_t k
            = std::size_t(std::lower_bound(band.begin(), band.end(), i) - band.begin());
        return coordinate[k] < median ? 0 : 1;
    };
    std::vector<std::vector<Index>> groups(2);
    std::vector<Index> serial;
    for (const Index c : m_shared_cells) {
        const std::size_t begin = m_node_offset[std::size_t(c)],
                          end = m_node_offset[std::size_t(c) + 1];
        const int s = side(m_node_list[begin]);
        bool one_side = true;
        for (std::size_t k = begin + 1; k < end && one_side; ++k)
            one_side = side(m_node_list[k]) == s;
        (one_side ? groups[std::size_t(s)] : serial).push_back(c);
    }
    m_shared_groups = std::move(groups);
    m_shared_cells = std::move(serial);
}

} // namespace polycut::elasticity
