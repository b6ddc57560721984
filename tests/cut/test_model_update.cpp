// After a cut appends cells and nodes, ElasticModel::update_cells (only the changed and new
// cells) must give the same system as a model built from scratch on the cut mesh.
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/elasticity/elastic_model.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>
#include <random>

using namespace polycut;

namespace {

elasticity::Material tissue() {
    elasticity::Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.3;
    return mat;
}

/// The base z = 0 fixed.
std::vector<std::uint8_t> fixed_for(const mesh::Mesh& mm) {
    std::vector<std::uint8_t> nodes(mm.rest.size(), 0);
    for (std::size_t i = 0; i < mm.rest.size(); ++i)
        nodes[i] = mm.rest[i].z() < 1e-12 ? 1 : 0;
    return elasticity::fix_nodes(nodes);
}

/// The rest positions moved by up to 1 mm per axis at random (a deformed state).
MatX3 jittered(const mesh::Mesh& m, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
    MatX3 x(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        x.row(i)
            = (m.rest[std::size_t(i)] + Vec3(jitter(rng), jitter(rng), jitter(rng))).transpose();
    return x;
}

/// The updated model and one built afresh on the same mesh give the same stiffness, forces and
/// mass at a random deformed state, corotated.
void expect_same_system(elasticity::ElasticModel& model, elasticity::ElasticModel& fresh,
    const mesh::Mesh& m, unsigned seed) {
    ASSERT_EQ(model.num_free_dofs(), fresh.num_free_dofs());
    const MatX3 x = jittered(m, seed);
    SparseMatrix K1 = model.make_matrix(), K2 = fresh.make_matrix();
    // The pattern is a function of the mesh: an incremental update must give the same arrays.
    ASSERT_EQ(K1.nonZeros(), K2.nonZeros());
    EXPECT_TRUE(std::equal(
        K1.outerIndexPtr(), K1.outerIndexPtr() + K1.outerSize() + 1, K2.outerIndexPtr()));
    EXPECT_TRUE(
        std::equal(K1.innerIndexPtr(), K1.innerIndexPtr() + K1.nonZeros(), K2.innerIndexPtr()));
    EXPECT_EQ(model.diagonal_slots(), fresh.diagonal_slots());
    VecX f1, f2;
    model.assemble(x, elasticity::ForceMode::Corotated, &K1, &f1);
    fresh.assemble(x, elasticity::ForceMode::Corotated, &K2, &f2);
    EXPECT_NEAR((MatX(K1) - MatX(K2)).norm(), 0.0, 1e-9 * MatX(K2).norm());
    EXPECT_NEAR((f1 - f2).norm(), 0.0, 1e-9 * f2.norm());
    EXPECT_NEAR((model.nodal_mass() - fresh.nodal_mass()).norm(), 0.0, 1e-12);
}

} // namespace

TEST(ModelUpdate, IncrementalUpdateAfterACutEqualsARebuild) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.03, 0.03, 0.02);
    g.cells = { 3, 3, 2 };
    mesh::Mesh m = mesh::hex_grid(g);
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    const auto version = model.topology_version();

    cut::Cutter cutter(m);
    const cut::CutReport report = cutter.split_by_plane(Vec3(0.013, 0.0, 0.0), Vec3(1, 0.2, 0.1));
    ASSERT_GT(report.cells_after, report.cells_before);
    ASSERT_GT(report.nodes_after, report.nodes_before);
    model.update_cells(report.changed_cells);
    model.set_fixed_dofs(fixed_for(m));
    EXPECT_GT(model.topology_version(), version);

    elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
    expect_same_system(model, fresh, m, 3);
}

TEST(ModelUpdate, ACellThatCannotBeMadeThrowsWithTheModelAsItWas) {
    // A cut whose piece the basis refuses is undone (sim::Simulation::settle_cut): the model
    // must still be that of the mesh before the cut, so the undo costs no rebuild. Here the cut
    // mesh's first changed cell is collapsed onto a point; update_cells() and rebuild_topology()
    // both throw, and with the mesh put back the model equals one built afresh on it.
    mesh::BoxGrid g;
    g.hi = Vec3(0.03, 0.03, 0.02);
    g.cells = { 3, 3, 2 };
    mesh::Mesh m = mesh::hex_grid(g);
    const mesh::Mesh before = m;
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    const auto topology = model.topology_version();
    const auto cells = model.cell_version();
    cut::Cutter cutter(m);
    const cut::CutReport report = cutter.split_by_plane(Vec3(0.013, 0.0, 0.0), Vec3(1, 0.2, 0.1));
    ASSERT_FALSE(report.changed_cells.empty());
    const Index bad = report.changed_cells.front();
    const Vec3 point = m.rest[std::size_t(m.cells[std::size_t(bad)].nodes.front())];
    for (Index n : m.cells[std::size_t(bad)].nodes)
        m.rest[std::size_t(n)] = point;
    EXPECT_ANY_THROW(model.update_cells(report.changed_cells));
    EXPECT_ANY_THROW(model.rebuild_topology());
    EXPECT_EQ(model.topology_version(), topology);
    EXPECT_EQ(model.cell_version(), cells);
    m = before; // the undo
    elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
    expect_same_system(model, fresh, m, 5);
}

TEST(ModelUpdate, CellsMergedAwayKeepTheSurvivorsDataAndEqualARebuild) {
    // A plane cutting the corner 1 mm off the cells around an interior node of a ~1 cm grid:
    // corner slivers of ~1e-4 of a cell, far above the node snapping distance, merged into
    // their neighbours (cells removed, CutReport::cell_map renumbers).
    mesh::BoxGrid g;
    g.hi = Vec3(0.05, 0.05, 0.05);
    g.cells = { 5, 5, 5 };
    mesh::Mesh m = mesh::hex_grid(g);
    // Graded spacing (a rectilinear grid, faces stay planar): cells of different sizes, so data
    // left under a shifted id would differ from the cell's own.
    auto graded = [](double t) { return t * (1 + 20 * t); };
    for (Vec3& X : m.rest)
        X = Vec3(graded(X.x()), graded(X.y()), graded(X.z()));
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    const auto version = model.topology_version();
    cut::Cutter cutter(m);
    const Vec3 n = Vec3(1, 1, 1).normalized();
    const Vec3 corner = Vec3::Constant(graded(0.01));
    // The normal points into the corner: the corner piece keeps the old cell id, so old cells
    // are merged away and every later cell id shifts.
    const cut::CutReport report = cutter.split_by_plane(corner + 1e-3 * n, -n);
    ASSERT_FALSE(report.cell_map.empty()) << "no sliver was merged away";
    ASSERT_FALSE(report.removed_cells.empty()) << "only cells of this cut were merged away";
    ASSERT_GT(report.slivers_merged, 0);
    ASSERT_TRUE(report.node_map.empty());
    model.update_cells(report.changed_cells, report.cell_map);
    model.set_fixed_dofs(fixed_for(m));
    EXPECT_GT(model.topology_version(), version);
    EXPECT_TRUE(model.nodes_kept_since(version)) << "no node was renumbered";

    elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
    expect_same_system(model, fresh, m, 5);
    // The explosion guard's rest extents moved with their cells: the body scaled by 2 stretches
    // every cell by exactly 2 (a stale extent of a smaller cell read as a larger stretch, and
    // the step after such a cut was undone as "exploded").
    MatX3 scaled(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        scaled.row(i) = 2 * m.rest[std::size_t(i)].transpose();
    EXPECT_NEAR(fresh.max_cell_stretch(scaled), 2.0, 1e-9);
    EXPECT_NEAR(model.max_cell_stretch(scaled), 2.0, 1e-9);
}

namespace {
/// A stroke of `steps` sweeps through the middle of a tet grid, each cut by one CutterT (the
/// splitting Cutter or the SnapCutter, progressive) and followed by ElasticModel::update_cells;
/// the model must equal a fresh one after every cut (the incremental pattern: only the columns
/// of nodes whose cells changed are rebuilt).
template <class CutterT> void stroke_keeps_model_equal_to_rebuild(unsigned seed) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.04, 0.03, 0.02);
    g.cells = { 8, 6, 4 };
    mesh::Mesh m = mesh::tet_grid(g);
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    CutterT cutter(m);
    const int steps = 5;
    int cuts = 0;
    for (int k = 0; k < steps; ++k) {
        // Oblique blade (not in a grid plane), from above the top into the block, advancing in x.
        const double x0 = 0.006 + 0.006 * k, x1 = x0 + 0.006;
        const Vec3 a(x0, 0.0137, 0.03), b(x0, 0.0151, 0.008), c(x1, 0.0139, 0.03),
            d(x1, 0.0153, 0.008);
        const std::vector<cut::Triangle> tris { { a, b, c }, { b, d, c } };
        const cut::CutReport r = cutter.cut(tris);
        if (r.changed_cells.empty() && r.cells_after == r.cells_before)
            continue;
        ++cuts;
        EXPECT_TRUE(r.node_map.empty()) << "this stroke was meant to keep node ids";
        model.update_cells(r.changed_cells, r.cell_map);
        model.set_fixed_dofs(fixed_for(m));
        elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
        expect_same_system(model, fresh, m, seed + unsigned(k));
    }
    EXPECT_GE(cuts, 4);
}
} // namespace

TEST(ModelUpdate, SplitStrokeThroughTetGridEqualsARebuildAfterEveryCut) {
    stroke_keeps_model_equal_to_rebuild<cut::Cutter>(11);
}

TEST(ModelUpdate, ANodeLeftWithoutCellsLosesItsDofsAndTheLaterOnesMoveDown) {
    // The cell-splitting cutter takes crack-front nodes of one cut out of the faces in the next
    // (docs/scenes.md), so a node can lose all its cells: its DOFs go and every later reduced DOF
    // moves down. Here the cell at the corner (0, 0, top) of a hex grid is removed: its corner
    // node, first of the top layer, is left without cells.
    mesh::BoxGrid g;
    g.hi = Vec3(0.03, 0.03, 0.02);
    g.cells = { 3, 3, 2 };
    mesh::Mesh m = mesh::hex_grid(g);
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    const Index before = model.num_free_dofs();
    Index corner = kNone;
    for (std::size_t i = 0; i < m.rest.size(); ++i)
        if ((m.rest[i] - Vec3(0, 0, 0.02)).norm() < 1e-12)
            corner = Index(i);
    ASSERT_NE(corner, kNone);
    std::vector<Index> cell_map(m.cells.size(), kNone);
    std::vector<mesh::Cell> kept;
    for (std::size_t c = 0; c < m.cells.size(); ++c) {
        const auto& nodes = m.cells[c].nodes;
        if (std::find(nodes.begin(), nodes.end(), corner) != nodes.end())
            continue;
        cell_map[c] = Index(kept.size());
        kept.push_back(m.cells[c]);
    }
    ASSERT_EQ(kept.size() + 1, m.cells.size());
    m.cells = std::move(kept);
    model.update_cells({}, cell_map);
    EXPECT_EQ(model.num_free_dofs(), before - 3);
    EXPECT_EQ(model.dof_map()[3 * std::size_t(corner)], kNone);
    ASSERT_LT(3 * std::size_t(corner) + 3, model.dof_map().size() - 3) << "later DOFs must exist";
    elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
    expect_same_system(model, fresh, m, 7);
}

TEST(ModelUpdate, SnapStrokeThroughTetGridEqualsARebuildAfterEveryCut) {
    stroke_keeps_model_equal_to_rebuild<cut::SnapCutter>(21);
}

TEST(ModelUpdate, ACutsCellsStayInTheirThreadOfTheAssembly) {
    // Threaded assembly splits cells by node ranges. A cut appends its nodes at the end; they
    // take the range of the cells that made them, so the cells a cut makes stay threaded
    // instead of all going to the serial part (ElasticModel::shared_cells), and the threaded
    // system still equals a rebuild's. A 6 x 6 x 4 tet grid cut by a plane through half its
    // cells in the first node range.
    mesh::BoxGrid g;
    g.hi = Vec3(0.06, 0.06, 0.04);
    g.cells = { 6, 6, 4 };
    mesh::Mesh m = mesh::tet_grid(g);
    const elasticity::Material mat = tissue();
    elasticity::ElasticModel model(m, mat, {}, fixed_for(m));
    model.set_threads(2);
    const Index shared_before = model.shared_cells();
    cut::Cutter cutter(m);
    const cut::CutReport report
        = cutter.split_by_plane(Vec3(0.0301, 0.0173, 0.0113), Vec3(0.3, 1, 0.2));
    const Index added = report.cells_after - report.cells_before;
    ASSERT_GT(added, 20);
    model.update_cells(report.changed_cells, report.cell_map); // slivers merged away too
    model.set_fixed_dofs(fixed_for(m));
    // Only the cut cells that straddle the two ranges join the serial part: far fewer than the
    // cells the cut made (104 of 194 did before).
    EXPECT_LT(model.shared_cells() - shared_before, added / 4)
        << "shared " << shared_before << " -> " << model.shared_cells() << ", " << added
        << " cells added";
    // The threaded assembly of the cut model equals the serial one to the order of sums.
    const MatX3 x = jittered(m, 5);
    SparseMatrix K2 = model.make_matrix(), K1 = model.make_matrix();
    VecX f2, f1;
    model.assemble(x, elasticity::ForceMode::Corotated, &K2, &f2);
    model.set_threads(1);
    model.assemble(x, elasticity::ForceMode::Corotated, &K1, &f1);
    EXPECT_NEAR((MatX(K1) - MatX(K2)).norm(), 0.0, 1e-12 * MatX(K1).norm());
    EXPECT_NEAR((f1 - f2).norm(), 0.0, 1e-12 * f1.norm());
    // And the updated model is the one a rebuild gives.
    elasticity::ElasticModel fresh(m, mat, {}, fixed_for(m));
    expect_same_system(model, fresh, m, 7);
}
