// Private to the meshing module: the pieces hex_slice() cuts the cubes into, and their merging
// into cells (003 sec. 10, sliver merging; hex_slice_merge.cpp).
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/meshing/hex_slice.hpp"

#include <functional>
#include <numeric>
#include <unordered_set>
#include <vector>

namespace polycut::meshing::detail {

using Loop = std::vector<Index>;

struct UnionFind {
    std::vector<Index> parent;
    explicit UnionFind(std::size_t n)
        : parent(n) {
        std::iota(parent.begin(), parent.end(), 0);
    }
    Index find(Index i) {
        while (parent[std::size_t(i)] != i)
            i = parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
        return i;
    }
    bool unite(Index a, Index b) {
        a = find(a);
        b = find(b);
        if (a == b)
            return false;
        parent[std::size_t(b)] = a;
        return true;
    }
};

/// One polyhedral piece of a cube (or a whole inner cube).
struct Piece {
    std::vector<Loop> loops; ///< outward face loops
    std::vector<long> square; ///< per loop: the grid square it lies on, or -1 (skin)
    double volume = 0; ///< [m^3]
    long cube = 0; ///< linear cube index
    bool hex = false;
};

/// The loop's node ids in ascending order (the key of a face shared by two pieces).
Loop sorted(Loop l);

/// Merges pieces into groups: cavities into their cube's largest piece, the two sides of holed
/// squares, and small pieces into the neighbour across their largest shared face. Returns the
/// group root of each piece.
/// `area` gives a grid-face loop's area [m^2]; `holed`: the grid squares with holes.
std::vector<Index> merge_pieces(const std::vector<Piece>& pieces,
    const std::function<double(const Loop&)>& area, const std::unordered_set<long>& holed,
    double threshold, HexSliceReport& report);

} // namespace polycut::meshing::detail
