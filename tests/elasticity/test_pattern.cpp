// The reduced stiffness pattern (ElasticModel::rebuild_pattern, built per node): the assembled K
// equals the dense sum of the cells' Ke over the free DOFs, every column's rows are strictly
// increasing, and the pattern holds exactly the DOF pairs of nodes that share a cell.
#include "helpers.hpp"

#include <set>

using namespace polycut;
using namespace polycut::elasticity;

namespace {

/// Checks K against the dense reference assembled from the cached cell matrices.
void expect_pattern_and_values(const mesh::Mesh& mesh, ElasticModel& model) {
    solve::SparseMatrix K = model.make_matrix();
    model.assemble(test::rest_matrix(mesh), ForceMode::Linear, &K, nullptr);
    const Index n = model.num_free_dofs();
    const auto& map = model.dof_map();
    MatX dense = MatX::Zero(n, n);
    std::set<std::pair<Index, Index>> pairs;
    for (Index c = 0; c < mesh.num_cells(); ++c) {
        const auto& nodes = mesh.cells[std::size_t(c)].nodes;
        const auto Ke = model.cell_stiffness(c);
        for (std::size_t p = 0; p < 3 * nodes.size(); ++p)
            for (std::size_t q = 0; q < 3 * nodes.size(); ++q) {
                const Index r = map[3 * std::size_t(nodes[p / 3]) + p % 3];
                const Index s = map[3 * std::size_t(nodes[q / 3]) + q % 3];
                if (r == kNone || s == kNone)
                    continue;
                dense(r, s) += Ke(Eigen::Index(p), Eigen::Index(q));
                pairs.insert({ r, s });
            }
    }
    EXPECT_EQ(std::size_t(K.nonZeros()), pairs.size()); // no entry missing, none extra
    for (Index c = 0; c < n; ++c)
        for (int k = K.outerIndexPtr()[c] + 1; k < K.outerIndexPtr()[c + 1]; ++k)
            ASSERT_LT(K.innerIndexPtr()[k - 1], K.innerIndexPtr()[k]) << "column " << c;
    const double scale = dense.cwiseAbs().maxCoeff();
    EXPECT_LE((MatX(K) - dense).cwiseAbs().maxCoeff(), 1e-13 * scale);
    for (Index r = 0; r < n; ++r)
        EXPECT_EQ(K.innerIndexPtr()[model.diagonal_slots()[std::size_t(r)]], r);
}

TEST(Pattern, TetGridWithPartlyFixedNodes) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.05, 0.04, 0.03);
    g.cells = { 5, 4, 3 };
    const mesh::Mesh mesh = mesh::tet_grid(g);
    std::vector<std::uint8_t> fixed(3 * mesh.rest.size(), 0);
    for (std::size_t i = 0; i < mesh.rest.size(); ++i) {
        if (mesh.rest[i].x() < 1e-9)
            fixed[3 * i] = fixed[3 * i + 1] = fixed[3 * i + 2] = 1; // clamped face
        if (mesh.rest[i].z() < 1e-9)
            fixed[3 * i + 2] = 1; // sliding floor: z only
        if (mesh.rest[i].y() > 0.04 - 1e-9)
            fixed[3 * i + 1] = 1; // symmetry plane: y only
    }
    Material mat;
    ElasticModel model(mesh, mat, basis::BasisOptions {}, fixed);
    expect_pattern_and_values(mesh, model);
}

TEST(Pattern, HexGridOfEightNodeCells) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.04, 0.03, 0.03);
    g.cells = { 4, 3, 3 };
    const mesh::Mesh mesh = mesh::hex_grid(g);
    std::vector<std::uint8_t> fixed(3 * mesh.rest.size(), 0);
    for (std::size_t i = 0; i < mesh.rest.size(); ++i)
        if (mesh.rest[i].x() < 1e-9)
            fixed[3 * i] = fixed[3 * i + 1] = fixed[3 * i + 2] = 1;
    Material mat;
    ElasticModel model(mesh, mat, basis::BasisOptions {}, fixed);
    expect_pattern_and_values(mesh, model);
}

} // namespace

namespace {
TEST(Pattern, MergedPolyhedralCells) {
    mesh::BoxGrid g;
    g.hi = Vec3(0.04, 0.04, 0.03);
    g.cells = { 4, 4, 3 };
    const mesh::Mesh mesh = mesh::merged_hex_grid(g, 0.5, 7);
    std::vector<std::uint8_t> fixed(3 * mesh.rest.size(), 0);
    for (std::size_t i = 0; i < mesh.rest.size(); ++i)
        if (mesh.rest[i].z() < 1e-9)
            fixed[3 * i + 2] = 1;
    fixed[0] = fixed[1] = 1;
    Material mat;
    ElasticModel model(mesh, mat, basis::BasisOptions {}, fixed);
    expect_pattern_and_values(mesh, model);
}
} // namespace
