// Editor::cells_near (core/cut/src/editor.hpp): the cells a sweep triangle can reach, found
// through a grid instead of a pass over the mesh, must include every cell the pass would find.
#include "editor.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>
#include <random>

using namespace polycut;

namespace {
// Every cell below `limit` whose bounds, grown by reach times their diagonal, overlap box.
std::vector<Index> brute(
    cut::detail::Editor& ed, const geometry::Aabb& box, double reach, Index limit) {
    std::vector<Index> out;
    for (Index c = 0; c < limit; ++c) {
        geometry::Aabb b = ed.bounds(c);
        const double r = reach * (b.hi - b.lo).norm();
        b.lo.array() -= r;
        b.hi.array() += r;
        if (b.overlaps(box))
            out.push_back(c);
    }
    return out;
}

void expect_superset(cut::detail::Editor& ed, std::mt19937& rng, double reach, int boxes) {
    std::uniform_real_distribution<double> at(-0.02, 0.12), size(0.0, 0.03);
    for (int k = 0; k < boxes; ++k) {
        geometry::Aabb box;
        const Vec3 lo(at(rng), at(rng), at(rng));
        box.extend(lo);
        box.extend(lo + Vec3(size(rng), size(rng), size(rng)));
        const Index limit = ed.m.num_cells();
        const std::vector<Index> near = ed.cells_near(box, limit);
        ASSERT_TRUE(std::is_sorted(near.begin(), near.end()));
        ASSERT_TRUE(std::adjacent_find(near.begin(), near.end()) == near.end());
        for (Index c : brute(ed, box, reach, limit))
            ASSERT_TRUE(std::binary_search(near.begin(), near.end(), c))
                << "cell " << c << " missed by box " << k;
        // A superset, but not the whole mesh for a small box.
        if ((box.hi - box.lo).maxCoeff() < 0.01) {
            EXPECT_LT(near.size(), std::size_t(limit) / 2);
        }
    }
}
/// Kuhn tets of an 8 x 8 x 8 grid over a 10 cm cube.
mesh::Mesh block() {
    mesh::BoxGrid g;
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(8, 8, 8);
    return mesh::tet_grid(g);
}
} // namespace

TEST(EditorGrid, CellsNearHoldEveryCellThePassOverTheMeshFinds) {
    mesh::Mesh m = block();
    cut::CutOptions opt;
    cut::detail::Editor ed(m, opt);
    std::mt19937 rng(11);
    const double reach = cut::detail::kSweepReach * opt.snap;
    expect_superset(ed, rng, reach, 200);
    // Nodes moved by up to 3 cm (their cells touched, their bounds changed beyond the buckets
    // they were filed in): a few, then more than an eighth
    // of the cells (the grid is made again), each time the same property.
    std::uniform_int_distribution<Index> node(0, m.num_nodes() - 1);
    std::uniform_real_distribution<double> shift(-0.03, 0.03); // beyond a bucket (~1 cm)
    for (int round : { 5, 400 }) {
        cut::CutReport report;
        ed.begin(report);
        for (int i = 0; i < round; ++i) {
            const Index n = node(rng);
            ed.move_node(n, m.rest[std::size_t(n)] + Vec3(shift(rng), shift(rng), shift(rng)));
        }
        expect_superset(ed, rng, reach, 200);
        ed.end();
    }
}

TEST(EditorGrid, CellsNearFollowTheCellsThroughARenumbering) {
    // Cells removed and the rest moved down (what merge_slivers does): the grid renames the ids
    // it filed instead of being built again, and still finds every cell the pass finds, and no
    // id twice; a map that does not keep the order makes it build again, with the same result.
    mesh::Mesh m = block();
    cut::CutOptions opt;
    cut::detail::Editor ed(m, opt);
    std::mt19937 rng(12);
    const double reach = cut::detail::kSweepReach * opt.snap;
    expect_superset(ed, rng, reach, 50); // the grid is built
    for (const bool keep_order : { true, false }) {
        const Index n = m.num_cells();
        std::vector<Index> map(std::size_t(n), kNone);
        std::vector<mesh::Cell> kept;
        for (Index c = 0; c < n; ++c)
            if (c % 7 != 3) {
                map[std::size_t(c)] = Index(kept.size());
                kept.push_back(m.cells[std::size_t(c)]);
            }
        if (!keep_order) { // the first two survivors change places
            std::swap(kept[0], kept[1]);
            std::swap(map[0], map[1]);
        }
        m.cells = std::move(kept);
        ed.renumber(map);
        expect_superset(ed, rng, reach, 200);
    }
}
