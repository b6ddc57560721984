// Merging of hex_slice()'s pieces into cells (hex_slice_merge.hpp).
#include "hex_slice_merge.hpp"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace polycut::meshing::detail {

Loop sorted(Loop l) {
    std::sort(l.begin(), l.end());
    return l;
}

std::vector<Index> merge_pieces(const std::vector<Piece>& pieces,
    const std::function<double(const Loop&)>& area, const std::unordered_set<long>& holed,
    double threshold, HexSliceReport& report) {
    const std::size_t n = pieces.size();
    UnionFind uf(n);
    // Twin loops: the same node set on the other side of a grid square.
    std::map<Loop, std::vector<std::pair<Index, std::size_t>>> by_key;
    for (std::size_t p = 0; p < n; ++p)
        for (std::size_t l = 0; l < pieces[p].loops.size(); ++l)
            if (pieces[p].square[l] >= 0)
                by_key[sorted(pieces[p].loops[l])].emplace_back(Index(p), l);
    std::unordered_map<long, Index> largest; // cube -> largest positive piece
    for (std::size_t p = 0; p < n; ++p) {
        auto [it, inserted] = largest.emplace(pieces[p].cube, Index(p));
        if (!inserted && pieces[p].volume > pieces[std::size_t(it->second)].volume)
            it->second = Index(p);
    }
    for (std::size_t p = 0; p < n; ++p)
        if (pieces[p].volume < 0) // a cavity's shell: part of the piece around it
            uf.unite(largest.at(pieces[p].cube), Index(p));
    for (const auto& [key, uses] : by_key)
        if (uses.size() == 2
            && holed.count(pieces[std::size_t(uses[0].first)].square[uses[0].second]))
            uf.unite(uses[0].first, uses[1].first);

    std::vector<double> volume(n, 0.0);
    for (std::size_t p = 0; p < n; ++p)
        volume[std::size_t(uf.find(Index(p)))] += pieces[p].volume;
    std::vector<Index> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](Index a, Index b) {
        return pieces[std::size_t(a)].volume < pieces[std::size_t(b)].volume;
    });
    for (int pass = 0; pass < 8; ++pass) {
        bool changed = false;
        for (Index p : order) {
            const Index root = uf.find(p);
            if (volume[std::size_t(root)] >= threshold)
                continue;
            // Shared grid-face area per neighbouring group, over all pieces of p's group.
            std::map<Index, double> shared;
            for (std::size_t q = 0; q < n; ++q) {
                if (uf.find(Index(q)) != root)
                    continue;
                for (std::size_t l = 0; l < pieces[q].loops.size(); ++l) {
                    if (pieces[q].square[l] < 0)
                        continue;
                    for (const auto& [other, ol] : by_key.at(sorted(pieces[q].loops[l]))) {
                        const Index r = uf.find(other);
                        if (r != root)
                            shared[r] += area(pieces[q].loops[l]);
                    }
                }
            }
            if (shared.empty())
                continue;
            const auto best = std::max_element(shared.begin(), shared.end(),
                [](const auto& a, const auto& b) { return a.second < b.second; });
            const double v = volume[std::size_t(root)] + volume[std::size_t(best->first)];
            uf.unite(best->first, root);
            volume[std::size_t(uf.find(root))] = v;
            ++report.merged;
            changed = true;
        }
        if (!changed)
            break;
    }
    std::vector<Index> group(n);
    for (std::size_t p = 0; p < n; ++p)
        group[p] = uf.find(Index(p));
    for (std::size_t p = 0; p < n; ++p)
        if (group[p] == Index(p) && volume[p] < threshold && volume[p] > 0)
            ++report.small_kept;
    return group;
}

} // namespace polycut::meshing::detail
