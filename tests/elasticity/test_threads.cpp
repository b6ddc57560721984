// Threaded assembly (ElasticModel::set_threads): the same K and forces as the serial loop up to
// the order of sums, bit-identical from run to run for one thread count, with few cells left to
// the serial part on a mesh numbered for locality.
#include "helpers.hpp"
#include "polycut/common/error.hpp"

#include <cstring>

using namespace polycut;
using namespace polycut::elasticity;

namespace {

struct Assembled {
    VecX K; ///< values of the reduced stiffness
    VecX f;
    std::vector<Mat3> R;
};

/// A 10 x 8 x 6 Kuhn tet grid with its x = 0 face fixed, bent by up to 20 degrees and rippled so
/// the rotations matter.
struct Fixture {
    mesh::Mesh mesh;
    std::unique_ptr<ElasticModel> model;
    MatX3 x;
    Fixture() {
        mesh::BoxGrid g;
        g.hi = Vec3(0.1, 0.08, 0.06);
        g.cells = { 10, 8, 6 };
        mesh = mesh::tet_grid(g);
        std::vector<std::uint8_t> fixed(mesh.rest.size(), 0);
        for (std::size_t i = 0; i < mesh.rest.size(); ++i)
            fixed[i] = mesh.rest[i].x() < 1e-9;
        Material mat;
        mat.youngs_modulus = 1e4;
        mat.poisson_ratio = 0.45;
        model = std::make_unique<ElasticModel>(mesh, mat, basis::BasisOptions {}, fix_nodes(fixed));
        x = test::rest_matrix(mesh);
        for (Index i = 0; i < x.rows(); ++i) {
            const double a = 3.5 * x(i, 0); // up to 20 degrees about y
            const Vec3 p = x.row(i).transpose();
            x.row(i) << p.x() * std::cos(a) + p.z() * std::sin(a) + 1e-3 * std::sin(40 * p.y()),
                p.y(), -p.x() * std::sin(a) + p.z() * std::cos(a);
        }
    }
    /// Assembles twice with a fresh model (the rotations' warm start is part of the history
    /// that determinism is about).
    Assembled assemble(int threads) {
        model = std::make_unique<ElasticModel>(
            mesh, model->material(), basis::BasisOptions {}, model->fixed_dofs());
        model->set_threads(threads);
        solve::SparseMatrix K = model->make_matrix();
        VecX f;
        // twice: the second starts from warm rotations, as in a time step
        model->assemble(x, ForceMode::Corotated, &K, &f);
        model->assemble(x, ForceMode::Corotated, &K, &f);
        Assembled a;
        a.K = Eigen::Map<const VecX>(K.valuePtr(), K.nonZeros());
        a.f = f;
        for (Index c = 0; c < mesh.num_cells(); ++c)
            a.R.push_back(model->cell_rotation(c));
        return a;
    }
};

bool bit_equal(const VecX& a, const VecX& b) {
    return a.size() == b.size()
        && std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}

} // namespace

TEST(ThreadedAssembly, TwoThreadsMatchOneToRoundOffAndRepeatBitForBit) {
    Fixture s;
    const Assembled one = s.assemble(1);
    EXPECT_EQ(s.model->shared_cells(), 0);
    const Assembled two = s.assemble(2);
    // a grid numbered x-fastest: the cells across the two node ranges are about one layer of
    // blocks (6 tets x 10 x 8 = 480 of 2,880), the rest split evenly
    EXPECT_GT(s.model->shared_cells(), 0);
    EXPECT_LT(s.model->shared_cells(), s.mesh.num_cells() / 5);
    // Of the shared cells, those on either side of the band's split run on the two threads:
    // only the blocks across the split (one column of the layer, ~48 of 480) stay serial.
    EXPECT_GT(s.model->serial_cells(), 0);
    EXPECT_LT(s.model->serial_cells(), s.model->shared_cells() / 4);
    // The node ranges are balanced by each cell's middle node, so both threads lose about as
    // many cells to the serial part: within 5 % of the cells (counted at their first node, all
    // cells across the bound went from the lower range: 546 cells apart).
    const std::vector<Index> per_thread = s.model->thread_cell_counts();
    ASSERT_EQ(per_thread.size(), 2u);
    EXPECT_LE(std::abs(per_thread[0] - per_thread[1]), s.mesh.num_cells() / 20);
    const double kscale = one.K.cwiseAbs().maxCoeff(), fscale = one.f.cwiseAbs().maxCoeff();
    EXPECT_LE((one.K - two.K).cwiseAbs().maxCoeff(), 1e-13 * kscale);
    EXPECT_LE((one.f - two.f).cwiseAbs().maxCoeff(), 1e-12 * fscale);
    for (std::size_t c = 0; c < one.R.size(); ++c)
        EXPECT_LE((one.R[c] - two.R[c]).cwiseAbs().maxCoeff(), 1e-12);
    const Assembled again = s.assemble(2);
    EXPECT_TRUE(bit_equal(two.K, again.K));
    EXPECT_TRUE(bit_equal(two.f, again.f));
    const Assembled three = s.assemble(3);
    EXPECT_LE((one.K - three.K).cwiseAbs().maxCoeff(), 1e-13 * kscale);
    EXPECT_TRUE(bit_equal(one.K, s.assemble(1).K));
}

TEST(ThreadedAssembly, RejectsZeroThreads) {
    Fixture s;
    EXPECT_THROW(s.model->set_threads(0), InputError);
}

TEST(ThreadedCellSetUp, CellsComputedInParallelAreBitIdenticalAndCountedOnce) {
    // ElasticModel::compute_cells runs the per-cell set-up (basis, quadrature, Ke, affine fit)
    // with the model's threads (rebuild_topology, update_cells after a cut). Each cell's result
    // is its own: one and two threads must give the same element stiffness to the bit, on
    // merged-hex polyhedra (mean value basis) as on tets, and count each basis once.
    mesh::BoxGrid g;
    g.hi = Vec3(0.06, 0.05, 0.04);
    g.cells = { 6, 5, 4 };
    const mesh::Mesh mesh = mesh::merged_hex_grid(g, 0.5, 7);
    std::vector<std::uint8_t> fixed(mesh.rest.size(), 0);
    for (std::size_t i = 0; i < mesh.rest.size(); ++i)
        fixed[i] = mesh.rest[i].x() < 1e-9;
    Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.45;
    std::vector<MatX> stiffness[2];
    long polyhedral[2] = { 0, 0 };
    for (int t = 0; t < 2; ++t) {
        ElasticModel model(mesh, mat, basis::BasisOptions {}, fix_nodes(fixed));
        model.set_threads(t + 1);
        model.rebuild_topology(); // the cells again, now with t + 1 threads
        for (Index c = 0; c < mesh.num_cells(); ++c)
            stiffness[t].push_back(model.cell_stiffness(c));
        polyhedral[t] = model.bases_built().polyhedral;
    }
    ASSERT_GT(polyhedral[0], 0);
    EXPECT_EQ(polyhedral[0], polyhedral[1]);
    long differing = 0;
    for (std::size_t c = 0; c < stiffness[0].size(); ++c)
        differing += stiffness[0][c].size() != stiffness[1][c].size()
            || std::memcmp(stiffness[0][c].data(), stiffness[1][c].data(),
                   sizeof(double) * std::size_t(stiffness[0][c].size()))
                != 0;
    EXPECT_EQ(differing, 0);
}
