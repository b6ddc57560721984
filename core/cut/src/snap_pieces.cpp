// Small pieces a face set would enclose are kept attached (002 sec. 3.2, step 3, on an irregular
// mesh): part of face snapping's dissection (snap_dissect.cpp).
#include "snap_model.hpp"

#include <algorithm>
#include <unordered_set>

namespace polycut::cut::snap {

// 002's closest-node selection on an irregular mesh can wrap a tet on the far side of the
// sweep: a tet with a face in the sweep plane whose apex node is marked by the tets around it,
// so the faces at the apex are selected too. Snapping the apex would flatten that tet; when the
// snap is refused (snap_min_aspect) the selected faces enclose the tet, which touches its side
// only at the apex node and would come off as a tiny extra piece. Such newly enclosed pieces of
// fewer than min_piece_cells tets are found by a bounded flood fill through the faces that stay
// interior, and their selected faces are dropped: the piece stays with the tets across them.
Index keep_small_pieces(State& s, std::unordered_set<Index>& take, std::vector<Index>& dropped) {
    const Index limit = s.opt.min_piece_cells;
    if (limit <= 0)
        return 0;
    std::vector<Index> seeds;
    for (Index f : take) {
        seeds.push_back(at(s.m.faces, f).owner);
        seeds.push_back(at(s.m.faces, f).neighbour);
    }
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    std::unordered_set<Index> done;
    Index merged = 0;
    for (Index seed : seeds) {
        if (done.count(seed))
            continue;
        std::vector<Index> piece { seed };
        std::unordered_set<Index> in { seed };
        for (std::size_t i = 0; i < piece.size() && Index(piece.size()) < limit; ++i)
            for (Index f : at(s.m.cells, piece[i]).faces) {
                const mesh::Face& face = at(s.m.faces, f);
                if (face.boundary() || take.count(f))
                    continue;
                const Index other = face.owner == piece[i] ? face.neighbour : face.owner;
                if (in.insert(other).second)
                    piece.push_back(other);
            }
        done.insert(piece.begin(), piece.end());
        if (Index(piece.size()) >= limit)
            continue;
        // Closed and small: glue it to the tet across its selected faces lying farthest on its
        // side of the sweep, dropping only the faces shared with that tet. Gluing it to more
        // tets could bridge the two sides where the cut folds around it.
        const SweepPlane& P = s.recent.back();
        auto side = [&](Index c) {
            Vec3 mid = Vec3::Zero();
            for (Index n : at(s.m.cells, c).nodes)
                mid += s.X(n) / 4.0;
            return P.distance(mid);
        };
        double own = 0;
        for (Index c : piece)
            own += side(c);
        Index join = kNone;
        double best = 0;
        for (Index c : piece)
            for (Index f : at(s.m.cells, c).faces)
                if (take.count(f)) {
                    const mesh::Face& face = at(s.m.faces, f);
                    const Index other = face.owner == c ? face.neighbour : face.owner;
                    if (side(other) * own > best) {
                        best = side(other) * own;
                        join = other;
                    }
                }
        std::vector<Index> drop;
        for (Index c : piece)
            for (Index f : at(s.m.cells, c).faces)
                if (take.count(f)
                    && (at(s.m.faces, f).owner == join || at(s.m.faces, f).neighbour == join))
                    drop.push_back(f);
        for (Index f : drop)
            take.erase(f);
        dropped.insert(dropped.end(), drop.begin(), drop.end());
        merged += drop.empty() ? 0 : 1;
    }
    return merged;
}

} // namespace polycut::cut::snap
