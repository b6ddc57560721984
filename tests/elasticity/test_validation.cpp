// Analytic validations of the linear static response: bar in uniaxial tension, column under its
// own weight, and the cantilever of 002 sec. 3.3 (Table 3.1).
#include "helpers.hpp"

#include <cmath>
#include <cstdlib>

using namespace polycut;
using namespace polycut::elasticity;

namespace {
class Bar : public ::testing::TestWithParam<bool> { };
} // namespace

TEST_P(Bar, UniaxialTensionMatchesFLOverEA) {
    // Bar [0, L] x [0, W] x [0, H] pulled by F along x. Rollers: u_x = 0 on x = 0, plus three
    // single components to remove the rigid motions without restraining the lateral contraction.
    const bool hexes = GetParam();
    const double L = 2.0, W = 0.4, H = 0.3, F = 150.0;
    Material mat;
    mat.youngs_modulus = 2e5;
    mat.poisson_ratio = 0.3;
    mesh::BoxGrid g;
    g.hi = Vec3(L, W, H);
    g.cells = { 8, 3, 2 };
    const mesh::Mesh m = hexes ? mesh::hex_grid(g) : mesh::tet_grid(g);
    std::vector<std::uint8_t> fixed(3 * std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        if (m.rest[std::size_t(i)].x() == 0.0)
            fixed[3 * std::size_t(i)] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 0, 0, 0)) + 1] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 0, 0, 0)) + 2] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 0, 3, 0)) + 2] = 1;
    ElasticModel model(m, mat, {}, fixed);
    const VecX f = test::traction_load(
        m, Vec3(F / (W * H), 0, 0), [&](const Vec3& p) { return p.x() == L; });
    EXPECT_NEAR(f.sum(), F, 1e-9 * F);
    const MatX3 X = test::rest_matrix(m);
    const MatX3 x = test::solve_linear_static(model, X, f);
    const double strain = F / (mat.youngs_modulus * W * H);
    for (Index i = 0; i < m.num_nodes(); ++i) {
        const Vec3 u = (x.row(i) - X.row(i)).transpose();
        const Vec3 p = X.row(i).transpose();
        EXPECT_NEAR(u.x(), strain * p.x(), 1e-9 * strain * L);
        EXPECT_NEAR(u.y(), -mat.poisson_ratio * strain * p.y(), 1e-9 * strain * L);
        EXPECT_NEAR(u.z(), -mat.poisson_ratio * strain * p.z(), 1e-9 * strain * L);
    }
}

INSTANTIATE_TEST_SUITE_P(P1AndQ1, Bar, ::testing::Values(false, true));

namespace {
class Column : public ::testing::TestWithParam<bool> { };
} // namespace

TEST_P(Column, OwnWeightMatchesQuadraticProfile) {
    // Column of height L along z on rollers at z = 0, gravity -z, nu = 0:
    // u_z(z) = -rho g (2 L z - z^2) / (2 E).
    const bool hexes = GetParam();
    const double L = 1.0, a = 0.2, rho = 1000, grav = 9.81;
    Material mat;
    mat.youngs_modulus = 1e6;
    mat.poisson_ratio = 0.0;
    mat.density = rho;
    mesh::BoxGrid g;
    g.hi = Vec3(a, a, L);
    g.cells = { 2, 2, 16 };
    const mesh::Mesh m = hexes ? mesh::hex_grid(g) : mesh::tet_grid(g);
    std::vector<std::uint8_t> fixed(3 * std::size_t(m.num_nodes()), 0);
    for (Index i = 0; i < m.num_nodes(); ++i)
        if (m.rest[std::size_t(i)].z() == 0.0)
            fixed[3 * std::size_t(i) + 2] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 0, 0, 0)) + 0] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 0, 0, 0)) + 1] = 1;
    fixed[3 * std::size_t(mesh::grid_node(g, 2, 0, 0)) + 1] = 1;
    ElasticModel model(m, mat, {}, fixed);
    VecX f = VecX::Zero(3 * m.num_nodes());
    for (Index i = 0; i < m.num_nodes(); ++i)
        f(3 * i + 2) = -model.nodal_mass()(i) * grav;
    const MatX3 X = test::rest_matrix(m);
    const MatX3 x = test::solve_linear_static(model, X, f);
    const double tip = rho * grav * L * L / (2 * mat.youngs_modulus);
    double worst = 0, lateral = 0;
    for (Index i = 0; i < m.num_nodes(); ++i) {
        const double z = X(i, 2);
        const double exact = -rho * grav * (2 * L * z - z * z) / (2 * mat.youngs_modulus);
        worst = std::max(worst, std::abs(x(i, 2) - X(i, 2) - exact));
        lateral = std::max(lateral, (x.row(i).head<2>() - X.row(i).head<2>()).norm());
    }
    std::printf(
        "[ info ] %s column: max |u_z - exact| / u_tip = %.3g, max lateral / u_tip = %.3g\n",
        hexes ? "Q1" : "P1", worst / tip, lateral / tip);
    if (hexes) {
        // Q1 on a regular grid with lumped (= consistent for a constant body force) loads is
        // nodally exact for this 1D problem.
        EXPECT_LT(worst, 1e-9 * tip);
        EXPECT_LT(lateral, 1e-9 * tip);
    } else {
        // The Kuhn split is anisotropic and its lumped mass is uneven (the block-diagonal nodes
        // get three times more), so the 3D P1 solution is not the 1D one at nodes. Compare the
        // cross-section averages of u_z, which converge; bound the lateral sway.
        double worst_mean = 0;
        for (int k = 0; k <= g.cells.z(); ++k) {
            double mean = 0;
            int count = 0;
            for (int j = 0; j <= g.cells.y(); ++j)
                for (int i = 0; i <= g.cells.x(); ++i, ++count)
                    mean += x(mesh::grid_node(g, i, j, k), 2) - X(mesh::grid_node(g, i, j, k), 2);
            mean /= count;
            const double z = L * k / g.cells.z();
            worst_mean = std::max(worst_mean,
                std::abs(mean + rho * grav * (2 * L * z - z * z) / (2 * mat.youngs_modulus)));
        }
        std::printf(
            "[ info ] P1 column: max layer-mean |u_z - exact| / u_tip = %.3g\n", worst_mean / tip);
        EXPECT_LT(worst_mean, 1e-3 * tip);
        EXPECT_LT(worst, 0.05 * tip);
        EXPECT_LT(lateral, 0.15 * tip);
    }
}

INSTANTIATE_TEST_SUITE_P(P1AndQ1, Column, ::testing::Values(false, true));

namespace {
struct TipResult {
    double mean_deflection = 0;
    double max_deflection = 0;
    Index nodes = 0;
};

/// Cantilever of 002 sec. 3.3: l = 1.2 m along x, d = 0.3 m along y, h = 0.2 m along z (the
/// load acts along -z, the height: y = 4 F l^3 / (E d h^3) = 8.64e-3 m), fixed at x = 0, 3 N
/// spread equally over the end-face nodes.
TipResult cantilever(int nx, bool hexes) {
    const double l = 1.2, d = 0.3, h = 0.2, F = 3.0;
    Material mat;
    mat.youngs_modulus = 1e6;
    mat.poisson_ratio = 0.0;
    mesh::BoxGrid g;
    g.hi = Vec3(l, d, h);
    g.cells = { nx, nx / 4, nx / 4 };
    const mesh::Mesh m = hexes ? mesh::hex_grid(g) : mesh::tet_grid(g);
    std::vector<std::uint8_t> node_fix(std::size_t(m.num_nodes()), 0);
    std::vector<Index> tip;
    for (Index i = 0; i < m.num_nodes(); ++i) {
        if (m.rest[std::size_t(i)].x() == 0.0)
            node_fix[std::size_t(i)] = 1;
        if (m.rest[std::size_t(i)].x() == l)
            tip.push_back(i);
    }
    ElasticModel model(m, mat, {}, fix_nodes(node_fix));
    VecX f = VecX::Zero(3 * m.num_nodes());
    for (Index i : tip)
        f(3 * i + 2) = -F / double(tip.size());
    const MatX3 X = test::rest_matrix(m);
    const MatX3 x = test::solve_linear_static(model, X, f);
    TipResult r;
    r.nodes = m.num_nodes();
    for (Index i : tip) {
        const double defl = X(i, 2) - x(i, 2);
        r.mean_deflection += defl / double(tip.size());
        r.max_deflection = std::max(r.max_deflection, defl);
    }
    return r;
}
} // namespace

TEST(Cantilever, P1ConvergesTowardBeamSolutionAndQ1BeatsP1) {
    // 002 Table 3.1 errors (%): 29.0, 15.1, 8.6, 5.2, 3.2 for 16, 24, 32, 40, 48 cells along l.
    // The unit test runs 16..32; POLYCUT_LARGE_TESTS=1 adds 40 and 48 (seconds each).
    const double exact = 8.64e-3;
    const bool large = std::getenv("POLYCUT_LARGE_TESTS") != nullptr;
    const double paper[] = { 29.0, 15.1, 8.6, 5.2, 3.2 };
    double previous = 1e9;
    int row = 0;
    for (int nx : { 16, 24, 32, 40, 48 }) {
        if (nx > 32 && !large)
            break;
        const TipResult p1 = cantilever(nx, false);
        const TipResult q1 = cantilever(nx, true);
        const double e1 = 100 * (exact - p1.mean_deflection) / exact;
        const double eq = 100 * (exact - q1.mean_deflection) / exact;
        std::printf("[ info ] %2dx%2dx%2d nodes %5d  P1 tip %.4e m err %6.2f %% (paper %4.1f %%)  "
                    "Q1 tip %.4e m err %6.2f %%\n",
            nx, nx / 4, nx / 4, int(p1.nodes), p1.mean_deflection, e1, paper[row],
            q1.mean_deflection, eq);
        // P1 tets are too stiff and converge monotonically from below.
        EXPECT_LT(p1.mean_deflection, previous == 1e9 ? 1e9 : 1.2 * exact);
        EXPECT_LT(std::abs(e1), previous);
        previous = std::abs(e1);
        // Within the paper's error at each resolution (+ 0.5 % slack: the seed's tet split is
        // not stated).
        EXPECT_LT(std::abs(e1), paper[row] + 0.5);
        // Q1 at the same node count is closer.
        EXPECT_LT(std::abs(eq), std::abs(e1));
        ++row;
    }
}
