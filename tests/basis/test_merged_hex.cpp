// Hex-dominant meshes with merged (elongated and non-convex L-shaped) cells, mesh::merged_hex_grid
// (issue 4 item 3), with the harmonic basis on the merged cells and Q1 on the hexes: the
// builder's invariants, partition of unity and linear precision, six rigid modes, the patch test
// on the assembled mesh, and the seed 002 sec. 3.3 cantilever (analytic tip deflection
// 8.64e-3 m) against the same grid of plain hexes.
#include "global_assembly.hpp"
#include "polycut/basis/cell_basis.hpp"
#include "polycut/basis/harmonic.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/builders.hpp"
#include "polycut/mesh/validate.hpp"
#include "polyhedral_cells.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace polycut::basis {
namespace {
using namespace testing;

BasisOptions harmonic_options(int degree) {
    BasisOptions o;
    o.poly = PolyBasis::Harmonic;
    o.rule = PolyRule::Reference;
    o.gauss_degree = degree;
    return o;
}

mesh::BoxGrid grid(Vec3 hi, Eigen::Vector3i cells) {
    mesh::BoxGrid g;
    g.hi = hi;
    g.cells = cells;
    return g;
}
} // namespace

TEST(MergedHexGrid, ConformingDeterministicWithPairsAndLs) {
    const auto g = grid(Vec3(1.0, 0.6, 0.4), { 5, 3, 2 });
    const auto m = mesh::merged_hex_grid(g, 0.6, 11);
    EXPECT_NO_THROW(mesh::validate(m));
    EXPECT_NEAR(m.rest_volume(), 0.24, 1e-12);
    int hexes = 0, pairs = 0, ls = 0, merged_blocks = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& cell = m.cells[std::size_t(c)];
        const auto loops = m.cell_face_loops(c);
        const bool convex = geometry::polyhedron_is_convex(m.rest, loops, 1e-9);
        if (cell.shape == mesh::CellShape::Hex) {
            ++hexes;
        } else if (cell.nodes.size() == 12 && loops.size() == 10) {
            ++pairs;
            merged_blocks += 2;
            EXPECT_TRUE(convex) << c;
        } else if (cell.nodes.size() == 16 && loops.size() == 14) {
            ++ls;
            merged_blocks += 3;
            EXPECT_FALSE(convex) << c;
        } else {
            ADD_FAILURE() << "unexpected cell " << c << " with " << cell.nodes.size() << " nodes";
        }
    }
    EXPECT_EQ(hexes + merged_blocks, 30);
    EXPECT_GT(pairs, 0);
    EXPECT_GT(ls, 0);
    EXPECT_NEAR(merged_blocks, 18, 2); // 0.6 of 30, rounded to whole groups
    // deterministic, and another seed gives another mesh
    const auto again = mesh::merged_hex_grid(g, 0.6, 11);
    ASSERT_EQ(again.num_cells(), m.num_cells());
    for (Index c = 0; c < m.num_cells(); ++c)
        EXPECT_EQ(again.cells[std::size_t(c)].nodes, m.cells[std::size_t(c)].nodes);
    EXPECT_EQ(mesh::merged_hex_grid(g, 0.0, 11).num_cells(), 30);
    EXPECT_THROW(mesh::merged_hex_grid(g, 1.5, 11), InputError);
}

TEST(MergedHexGrid, HarmonicCellsReproduceLinearFieldsWithSixRigidModes) {
    const auto m = mesh::merged_hex_grid(grid(Vec3(1.0, 0.6, 0.4), { 5, 3, 2 }), 0.6, 11);
    const auto C = isotropic_c(1.0, 0.3);
    int checked = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        if (m.cells[std::size_t(c)].shape != mesh::CellShape::Polyhedron)
            continue;
        const auto geo = cell_geometry(m, c);
        const HarmonicCell cell(geo);
        const auto ci = integrate_cell(m, c, harmonic_options(2));
        double worst = 0;
        VecX phi;
        for (const auto& x : ci.points) {
            cell.evaluate(x, phi);
            Vec3 rep = Vec3::Zero();
            for (Index i = 0; i < cell.num_nodes(); ++i)
                rep += phi[i] * geo.nodes[std::size_t(i)];
            worst = std::max({ worst, std::abs(phi.sum() - 1), (rep - x).norm() / cell.size() });
        }
        EXPECT_LT(worst, 1e-12) << "cell " << c; // partition of unity, linear precision
        EXPECT_NEAR(ci.lumped_volume.sum(), m.cell_volume(c), 1e-10 * m.cell_volume(c));
        const MatX K = stiffness(ci, C);
        EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
        const VecX ev = Eigen::SelfAdjointEigenSolver<MatX>(K).eigenvalues();
        const double top = ev[ev.size() - 1]; // ascending
        for (int k = 0; k < 6; ++k)
            EXPECT_LT(std::abs(ev[k]), 1e-11 * top) << "cell " << c << " k=" << k;
        EXPECT_GT(ev[6], 1e-6 * top) << "cell " << c;
        ++checked;
    }
    EXPECT_GT(checked, 4);
}

TEST(MergedHexGrid, PatchTest) {
    // Linear displacement on the boundary nodes: the interior nodes must follow it. Exact for
    // the hexes; the harmonic cells' C0 mismatch (~1 %, 001 sec. 5) leaves a small error.
    const auto m = mesh::merged_hex_grid(grid(Vec3(1.0, 0.8, 0.8), { 5, 4, 4 }), 0.7, 3);
    const auto C = isotropic_c(1.0, 0.3);
    const auto K = assemble(m, harmonic_options(4), C);
    Mat3 G;
    G << 0.01, 0.003, -0.002, 0.004, -0.02, 0.005, 0.001, 0.006, 0.015;
    std::vector<bool> fixed(std::size_t(3 * m.num_nodes()), false);
    VecX exact(3 * m.num_nodes()), u = VecX::Zero(3 * m.num_nodes());
    for (Index i = 0; i < m.num_nodes(); ++i)
        exact.segment<3>(3 * i) = G * m.rest[std::size_t(i)];
    for (Index f : m.boundary_faces())
        for (Index v : m.faces[std::size_t(f)].nodes)
            for (int d = 0; d < 3; ++d) {
                fixed[std::size_t(3 * v + d)] = true;
                u[3 * v + d] = exact[3 * v + d];
            }
    u = solve_with_fixed(K, VecX::Zero(3 * m.num_nodes()), fixed, u);
    const double err = (u - exact).lpNorm<Eigen::Infinity>() / exact.lpNorm<Eigen::Infinity>();
    std::printf("merged hex grid patch test: max interior error %.3e (relative)\n", err);
    EXPECT_LT(err, 5e-3);
}

TEST(MergedHexGrid, Cantilever) {
    // Seed 002 sec. 3.3: 1.2 x 0.3 x 0.2 m, E = 1 MPa, nu = 0, -3 N on the free end: tip
    // deflection 8.64e-3 m. 24 x 6 x 4 blocks, half of them merged into pairs and L triples.
    const auto g = grid(Vec3(1.2, 0.3, 0.2), { 24, 6, 4 });
    const auto C = isotropic_c(1e6, 0.0);
    auto tip = [&](const mesh::Mesh& m) {
        const auto K = assemble(m, harmonic_options(2), C);
        VecX f = VecX::Zero(3 * m.num_nodes()), u = VecX::Zero(3 * m.num_nodes());
        std::vector<bool> fixed(std::size_t(3 * m.num_nodes()), false);
        for (Index i = 0; i < m.num_nodes(); ++i)
            if (m.rest[std::size_t(i)].x() < 1e-9)
                fixed[std::size_t(3 * i)] = fixed[std::size_t(3 * i + 1)]
                    = fixed[std::size_t(3 * i + 2)] = true;
        const double area = 0.3 * 0.2;
        for (Index fi : m.boundary_faces()) {
            const auto& nodes = m.faces[std::size_t(fi)].nodes;
            bool end = true;
            for (Index v : nodes)
                end = end && m.rest[std::size_t(v)].x() > 1.2 - 1e-9;
            if (!end)
                continue;
            // quads of the end face: a quarter of the face's share of the load per node
            const double share = (0.3 / 6) * (0.2 / 4) / area;
            for (Index v : nodes)
                f[3 * v + 2] += -3.0 * share / double(nodes.size());
        }
        u = solve_with_fixed(K, f, fixed, u);
        double sum = 0;
        int count = 0;
        for (Index i = 0; i < m.num_nodes(); ++i)
            if (m.rest[std::size_t(i)].x() > 1.2 - 1e-9) {
                sum += u[3 * i + 2];
                ++count;
            }
        return -sum / count;
    };
    const double merged = tip(mesh::merged_hex_grid(g, 0.5, 5));
    const double hexes = tip(mesh::hex_grid(g));
    const double exact = 8.64e-3;
    std::printf("cantilever tip: merged hex grid %.4e m (%+.2f %%), hex grid %.4e m (%+.2f %%)\n",
        merged, 100 * (merged / exact - 1), hexes, 100 * (hexes / exact - 1));
    EXPECT_NEAR(merged, exact, 0.05 * exact);
    EXPECT_NEAR(merged, hexes, 0.03 * hexes);
}

} // namespace polycut::basis
