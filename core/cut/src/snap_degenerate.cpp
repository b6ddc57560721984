// Degeneracy removal (002 sec. 3.2.3).
#include "snap_state.hpp"

namespace polycut::cut::snap {

void remove_degeneracies(State& s) {
    for (Index c = 0; c < s.m.num_cells(); ++c)
        if (at(s.changed, c) && s.aspect(c) < s.opt.degenerate_aspect)
            ++s.stats.degenerate_left;
}

} // namespace polycut::cut::snap
