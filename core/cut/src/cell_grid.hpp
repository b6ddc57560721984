// A uniform grid of cell boxes shared by both cutters (issue 12 item 5: a sweep triangle costs
// what lies near it, not a pass over the mesh): cells filed by their boxes when it is built,
// the cells touched since listed apart, the cells added since always candidates. The owner
// decides when to build it again.
#pragma once

#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace polycut::cut::detail {

class CellGrid {
public:
    /// Files cells [0, n) by box_of(c) (about one cell per bucket; an empty box is not filed).
    void build(Index n, const std::function<geometry::Aabb(Index)>& box_of);
    /// Forgets the grid (the cells were renumbered): the owner builds it again.
    void invalidate() { m_ok = false; }
    /// The cells were renumbered by `map` (old id -> new id, kNone: removed; ids past its end
    /// removed) while keeping their boxes: the filed ids are renamed, O(filed entries), instead
    /// of a new build (every cell's box again: ~3.5 ms on a 26k-cell organ). The map must keep
    /// the survivors' order (a compaction); otherwise the grid is forgotten.
    void renumber(const std::vector<Index>& map);
    /// Cell c's box may have changed since the build.
    void touch(Index c);
    /// Whether the owner should build the grid again before querying the first n cells: not
    /// built, or the cells every query returns unfiled (touched or added since the build) past
    /// an eighth of them, or many cells gone since.
    bool stale(Index n) const {
        const std::size_t added = n > m_built ? std::size_t(n - m_built) : 0;
        return !m_ok || m_built > n + 1024 || m_dirty.size() + added > 64 + std::size_t(n) / 8;
    }
    /// Cells below n that may overlap `box`: filed in a bucket it overlaps, touched since the
    /// build or added since; a superset in increasing id order (callers test the boxes
    /// themselves). Valid until the next query.
    const std::vector<Index>& query(const geometry::Aabb& box, Index n);

private:
    bool m_ok = false;
    Index m_built = 0;
    Vec3 m_lo = Vec3::Zero();
    double m_h = 1; ///< bucket edge [m]
    std::array<int, 3> m_dims { 0, 0, 0 };
    std::vector<int> m_start; ///< bucket b holds m_cells[m_start[b] .. m_start[b + 1])
    std::vector<Index> m_cells;
    std::vector<Index> m_dirty;
    std::vector<char> m_in_dirty;
    std::vector<std::uint32_t> m_stamp;
    std::uint32_t m_now = 0;
    std::vector<Index> m_found;

    /// Buckets [lo, hi] per axis that b overlaps, clamped; false when b lies outside the grid.
    bool range(const geometry::Aabb& b, std::array<int, 3>& lo, std::array<int, 3>& hi) const;
    std::size_t bucket(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(m_dims[1]) + std::size_t(y)) * std::size_t(m_dims[0])
            + std::size_t(x);
    }
};

} // namespace polycut::cut::detail
