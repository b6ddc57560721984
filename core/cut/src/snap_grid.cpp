// The snap cutter's spatial index of tet rest bounds (State::candidates, a detail::CellGrid):
// a triangle's candidates are the tets in the buckets its box overlaps, the touched ones and
// the ones appended since the build, so each triangle costs what lies near it instead of a pass
// over the mesh (issue 12 item 5). The grid is built again when CellGrid::stale() says so or
// after a compaction renumbered the tets (rebuild_faces()).
#include "checks.hpp"
#include "snap_state.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace polycut::cut::snap {

const std::vector<Index>& State::candidates(const geometry::Aabb& b) {
    const Index n = m.num_cells();
    if (grid.stale(n))
        grid.build(n, [&](Index c) { return bounds(c); });
    const std::vector<Index>& found = grid.query(b, n);
    if (detail::incremental_checks()) {
        // Every tet whose bounds overlap b must be among the candidates.
        for (Index c = 0; c < n; ++c)
            if (bounds(c).overlaps(b) && !std::binary_search(found.begin(), found.end(), c))
                throw std::logic_error(
                    "snap cutter: the cell grid misses tet " + std::to_string(c));
    }
    return found;
}

} // namespace polycut::cut::snap
