// Hex-dominant meshes with merged cells (issue 4 item 3): a hex grid in which random groups of
// face-adjacent blocks (pairs, and L-shaped triples) are merged into single polyhedra. A pair is
// an elongated box whose side faces stay split at the middle (so it still conforms to its
// neighbours: 12 nodes, 10 faces, two nodes in the middle of straight edges); an L triple is a
// non-convex polyhedron (16 nodes, 14 faces). Test meshes for the harmonic basis, which handles
// non-convex cells (seed 001 sec. 5); tets stay P1 and hexes Q1 around them.
#include "polycut/common/error.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <random>

namespace polycut::mesh {
namespace {
using Block = std::array<int, 3>;

/// Outward loops of block b, as (corner offsets) x 4 per face, in -x +x -y +y -z +z order.
constexpr int kFaceCorners[6][4][3] = {
    { { 0, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 0, 1, 0 } },
    { { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 1, 0, 1 } },
    { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 1 }, { 0, 0, 1 } },
    { { 0, 1, 0 }, { 0, 1, 1 }, { 1, 1, 1 }, { 1, 1, 0 } },
    { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 1, 0, 0 } },
    { { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } },
};

std::vector<std::vector<Index>> block_loops(const BoxGrid& g, const Block& b) {
    std::vector<std::vector<Index>> loops;
    for (const auto& face : kFaceCorners) {
        std::vector<Index> loop;
        for (const auto& o : face)
            loop.push_back(grid_node(g, b[0] + o[0], b[1] + o[1], b[2] + o[2]));
        loops.push_back(std::move(loop));
    }
    return loops;
}

/// Unit step along axis a (0-2) in direction s (+-1).
Block step(const Block& b, int axis, int sign) {
    Block n = b;
    n[std::size_t(axis)] += sign;
    return n;
}
} // namespace

Mesh merged_hex_grid(const BoxGrid& grid, double merge_fraction, unsigned seed) {
    if (grid.cells.minCoeff() < 1)
        throw InputError("/cells", "every grid dimension must be >= 1");
    if (!(merge_fraction >= 0 && merge_fraction <= 1))
        throw InputError("/merge_fraction", "must lie in [0, 1]");
    const Mesh hexes = hex_grid(grid);
    const int nx = grid.cells.x(), ny = grid.cells.y(), nz = grid.cells.z();
    const auto id = [&](const Block& b) { return std::size_t(b[0] + nx * (b[1] + ny * b[2])); };
    const auto inside = [&](const Block& b) {
        return b[0] >= 0 && b[1] >= 0 && b[2] >= 0 && b[0] < nx && b[1] < ny && b[2] < nz;
    };
    const std::size_t total = std::size_t(nx) * std::size_t(ny) * std::size_t(nz);
    std::vector<Block> order;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                order.push_back({ i, j, k });
    std::mt19937 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);

    std::vector<bool> used(total, false);
    std::vector<std::vector<Block>> groups;
    std::size_t merged = 0;
    const auto target = std::size_t(merge_fraction * double(total) + 0.5);
    for (const Block& a : order) {
        if (merged >= target)
            break;
        if (used[id(a)])
            continue;
        // candidate groups around a: pairs along the 6 directions, L triples with the corner at a
        std::vector<std::vector<Block>> candidates;
        const bool want_l = rng() % 2 == 0;
        for (int axis = 0; axis < 3; ++axis)
            for (int sign : { -1, 1 }) {
                const Block b = step(a, axis, sign);
                if (!inside(b) || used[id(b)])
                    continue;
                if (!want_l) {
                    candidates.push_back({ a, b });
                    continue;
                }
                for (int axis2 = 0; axis2 < 3; ++axis2)
                    for (int sign2 : { -1, 1 }) {
                        const Block c = step(a, axis2, sign2);
                        if (axis2 != axis && inside(c) && !used[id(c)])
                            candidates.push_back({ a, b, c });
                    }
            }
        if (candidates.empty())
            continue;
        const auto& pick = candidates[rng() % candidates.size()];
        for (const Block& b : pick)
            used[id(b)] = true;
        merged += pick.size();
        groups.push_back(pick);
    }
    for (const Block& b : order)
        if (!used[id(b)])
            groups.push_back({ b });
    // deterministic cell order: by the smallest block id of each group
    std::sort(groups.begin(), groups.end(), [&](const auto& p, const auto& q) {
        const auto lo = [&](const std::vector<Block>& g) {
            std::size_t m = total;
            for (const Block& b : g)
                m = std::min(m, id(b));
            return m;
        };
        return lo(p) < lo(q);
    });

    // A merged cell: the member blocks' outward loops minus the faces two members share.
    std::vector<std::vector<std::vector<Index>>> cells;
    for (const auto& group : groups) {
        std::map<std::vector<Index>, int> count;
        std::vector<std::vector<Index>> all;
        for (const Block& b : group)
            for (auto& loop : block_loops(grid, b)) {
                auto key = loop;
                std::sort(key.begin(), key.end());
                ++count[key];
                all.push_back(std::move(loop));
            }
        std::vector<std::vector<Index>> loops;
        for (auto& loop : all) {
            auto key = loop;
            std::sort(key.begin(), key.end());
            if (count[key] == 1)
                loops.push_back(std::move(loop));
        }
        cells.push_back(std::move(loops));
    }
    Mesh mesh = Mesh::from_polyhedra(hexes.rest, cells);
    validate(mesh);
    return mesh;
}

} // namespace polycut::mesh
