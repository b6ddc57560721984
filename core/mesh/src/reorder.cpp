// Reverse Cuthill-McKee node order and cell order for locality (see reorder.hpp).
#include "polycut/mesh/reorder.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/cuthill_mckee_ordering.hpp>
#include <numeric>
#include <utility>

namespace polycut::mesh {

std::vector<Index> rcm_node_order(const Mesh& m) {
    using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS,
        boost::property<boost::vertex_color_t, boost::default_color_type,
            boost::property<boost::vertex_degree_t, int>>>;
    const std::size_t n = m.rest.size();
    // unique undirected edges, so vertex degrees count neighbours, not shared cells
    std::vector<std::pair<Index, Index>> edges;
    std::vector<std::uint8_t> used(n, 0);
    for (const Cell& c : m.cells)
        for (std::size_t a = 0; a < c.nodes.size(); ++a) {
            used[std::size_t(c.nodes[a])] = 1;
            for (std::size_t b = a + 1; b < c.nodes.size(); ++b)
                edges.emplace_back(
                    std::min(c.nodes[a], c.nodes[b]), std::max(c.nodes[a], c.nodes[b]));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    Graph g(n);
    for (const auto& [a, b] : edges)
        boost::add_edge(std::size_t(a), std::size_t(b), g);
    std::vector<std::size_t> old_of_new(n);
    boost::cuthill_mckee_ordering(
        g, old_of_new.rbegin(), boost::get(boost::vertex_color, g), boost::make_degree_map(g));
    std::vector<Index> new_of_old(n, kNone);
    Index next = 0;
    for (std::size_t old : old_of_new)
        if (used[old])
            new_of_old[old] = next++;
    for (std::size_t i = 0; i < n; ++i)
        if (!used[i])
            new_of_old[i] = next++;
    return new_of_old;
}

void renumber_nodes(Mesh& m, const std::vector<Index>& new_of_old) {
    const std::size_t n = m.rest.size();
    if (new_of_old.size() != n)
        throw InputError("new_of_old", "needs one entry per node");
    std::vector<Vec3> rest(n);
    std::vector<std::uint8_t> hit(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const Index k = new_of_old[i];
        if (k < 0 || std::size_t(k) >= n || hit[std::size_t(k)])
            throw InputError("new_of_old", "is not a permutation of the nodes");
        hit[std::size_t(k)] = 1;
        rest[std::size_t(k)] = m.rest[i];
    }
    m.rest = std::move(rest);
    for (Cell& c : m.cells)
        for (Index& v : c.nodes)
            v = new_of_old[std::size_t(v)];
    for (Face& f : m.faces)
        for (Index& v : f.nodes)
            v = new_of_old[std::size_t(v)];
}

void sort_cells_by_nodes(Mesh& m) {
    const std::size_t count = m.cells.size();
    std::vector<std::vector<Index>> keys(count);
    for (std::size_t c = 0; c < count; ++c) {
        keys[c] = m.cells[c].nodes;
        std::sort(keys[c].begin(), keys[c].end());
    }
    std::vector<Index> old_of_new(count);
    std::iota(old_of_new.begin(), old_of_new.end(), Index(0));
    std::stable_sort(old_of_new.begin(), old_of_new.end(),
        [&](Index a, Index b) { return keys[std::size_t(a)] < keys[std::size_t(b)]; });
    std::vector<Index> new_of_old(count);
    for (std::size_t k = 0; k < count; ++k)
        new_of_old[std::size_t(old_of_new[k])] = Index(k);
    std::vector<Cell> cells(count);
    for (std::size_t k = 0; k < count; ++k)
        cells[k] = std::move(m.cells[std::size_t(old_of_new[k])]);
    m.cells = std::move(cells);
    const auto map = [&](Index c) {
        return c >= 0 && std::size_t(c) < count ? new_of_old[std::size_t(c)] : c;
    };
    for (Cell& c : m.cells)
        c.parent = map(c.parent);
    for (Face& f : m.faces) {
        f.owner = map(f.owner);
        f.neighbour = map(f.neighbour);
    }
}

std::vector<Index> reorder_for_locality(Mesh& m) {
    std::vector<Index> order = rcm_node_order(m);
    renumber_nodes(m, order);
    sort_cells_by_nodes(m);
    return order;
}

Index node_bandwidth(const Mesh& m) {
    Index band = 0;
    for (const Cell& c : m.cells) {
        const auto [lo, hi] = std::minmax_element(c.nodes.begin(), c.nodes.end());
        if (lo != c.nodes.end())
            band = std::max(band, *hi - *lo);
    }
    return band;
}

} // namespace polycut::mesh
