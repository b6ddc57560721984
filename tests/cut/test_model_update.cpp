// After a cut appends cells and nodes, ElasticModel::update_cells (only the changed and new
// cells) must give the same system as a model built from scratch on the cut mesh.
#include "polycut/cut/cutter.hpp"
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

/// The updated model and one built afresh on the same mesh give the same stiffness, forces and
/// mass at a random deformed state, corotated.
void expect_same_system(elasticity::ElasticModel& model, elasticity::ElasticModel& fresh,
    const mesh::Mesh& m, unsigned seed) {
    ASSERT_EQ(model.num_free_dofs(), fresh.num_free_dofs());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
    MatX3 x(m.num_nodes(), 3);
    for (Index i = 0; i < m.num_nodes(); ++i)
        x.row(i)
            = (m.rest[std::size_t(i)] + Vec3(jitter(rng), jitter(rng), jitter(rng))).transpose();
    solve::SparseMatrix K1 = model.make_matrix(), K2 = fresh.make_matrix();
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
