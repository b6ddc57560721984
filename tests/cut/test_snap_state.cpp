// snap::State's list of the cells a call changed (core/cut/src/snap_state.hpp): the passes of
// degeneracy removal and dissection over the changed tets read it instead of scanning every
// tet, so it must name exactly the flagged tets, in id order, whatever happened since.
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/mesh/builders.hpp"
#include "snap_state.hpp"

#include <gtest/gtest.h>
#include <vector>

using namespace polycut;

namespace {
std::vector<Index> flagged(const cut::snap::State& s) {
    std::vector<Index> out;
    for (Index c = 0; c < Index(s.changed.size()); ++c)
        if (s.changed[std::size_t(c)])
            out.push_back(c);
    return out;
}
} // namespace

TEST(SnapState, ChangedCellsAreTheFlaggedTetsInIdOrder) {
    mesh::BoxGrid grid;
    grid.cells = { 3, 3, 3 };
    mesh::Mesh m = mesh::tet_grid(grid);
    cut::snap::State s(m, cut::SnapOptions {});
    cut::CutReport report;
    s.begin(report);
    EXPECT_TRUE(s.changed_cells().empty());
    // Touched out of order and twice, as the edits of a call do.
    for (Index c : { 40, 7, 40, 99, 7, 0, 161 })
        s.touch(c);
    EXPECT_EQ(s.changed_cells(), (std::vector<Index> { 0, 7, 40, 99, 161 }));
    EXPECT_EQ(s.touched, 5);
    // Unflagged (a deleted tet), then flagged again: listed once while flagged.
    s.changed[7] = 0;
    EXPECT_EQ(s.changed_cells(), flagged(s));
    s.touch(7);
    EXPECT_EQ(s.changed_cells(), flagged(s));
    // Cut off by a taken-back split (the arrays shrink): only the cells that remain.
    s.changed.resize(100);
    EXPECT_EQ(s.changed_cells(), (std::vector<Index> { 0, 7, 40, 99 }));
    s.changed.resize(std::size_t(m.num_cells()), 0);
    // The next call starts with none.
    s.begin(report);
    EXPECT_TRUE(s.changed_cells().empty());
    s.end();
}
