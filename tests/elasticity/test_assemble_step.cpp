// ElasticModel::assemble_step (the implicit step's matrix without a pass over K): the kernels'
// scaled blocks plus a diagonal term, and their product with the velocities, against assemble()
// followed by the scaling, the diagonal and the product done on the assembled K, for every
// kernel (batched P1 tets with both scatters, hexes, 12- and 16-node merged polyhedra), partly
// fixed nodes, one and two threads; and the refusal of the nodal volumetric term, which has no
// step product.
#include "helpers.hpp"

using namespace polycut;
using namespace polycut::elasticity;

namespace {

/// A deformed, moving state of the mesh: bent up to ~17 degrees about y, rippled, with
/// velocities that vary per node.
void deform(const mesh::Mesh& m, MatX3& x, MatX3& v) {
    x = test::rest_matrix(m);
    v.resize(x.rows(), 3);
    for (Index i = 0; i < x.rows(); ++i) {
        const Vec3 p = x.row(i).transpose();
        const double a = 3.0 * p.x();
        x.row(i) << p.x() * std::cos(a) + p.z() * std::sin(a) + 1e-3 * std::sin(40 * p.y()), p.y(),
            -p.x() * std::sin(a) + p.z() * std::cos(a);
        v.row(i) << std::sin(7 * double(i)), 0.3 * std::cos(3 * double(i)), 0.1 * double(i % 5);
    }
}

/// The relative max difference of assemble_step() from the reference made of assemble().
struct Difference {
    double A = 0, f = 0, kv = 0;
};

Difference compare(const mesh::Mesh& m, const std::vector<std::uint8_t>& fixed, int threads,
    const basis::BasisOptions& basis = {}) {
    Material mat;
    mat.youngs_modulus = 1e4;
    mat.poisson_ratio = 0.45;
    MatX3 x, v;
    deform(m, x, v);
    // two models with the same history (the corotation's warm start is part of it)
    ElasticModel ref(m, mat, basis, fixed), step(m, mat, basis, fixed);
    ref.set_threads(threads);
    step.set_threads(threads);
    solve::SparseMatrix K = ref.make_matrix(), A = step.make_matrix();
    VecX f_ref, f, kv;
    const double scale = 2.9e-4; // h^2 + h beta at h = 1/60 s, beta = 0.01 s
    // v zero at fixed DOFs, as assemble_step() asks
    for (std::size_t k = 0; k < fixed.size(); ++k)
        if (fixed[k])
            v.data()[k] = 0;
    // a diagonal term of the size of the step's mass term, different per DOF
    VecX diagonal(step.num_free_dofs());
    for (Index r = 0; r < diagonal.size(); ++r)
        diagonal(r) = 1e-3 * (1.0 + 0.1 * double(r % 7));
    for (int pass = 0; pass < 2; ++pass) { // cold, then warm rotations
        ref.assemble(x, ForceMode::Corotated, &K, &f_ref);
        EXPECT_TRUE(step.assemble_step(x, ForceMode::Corotated, scale, diagonal, v, A, f, kv));
    }
    EXPECT_EQ(A.nonZeros(), K.nonZeros());
    VecX v_r;
    ref.reduce(Eigen::Map<const VecX>(v.data(), v.size()), v_r);
    const VecX kv_ref = scale * (K * v_r);
    VecX kv_r;
    step.reduce(kv, kv_r);
    const MatX Kd = scale * MatX(K) + MatX(diagonal.asDiagonal());
    Difference d;
    d.A = (MatX(A) - Kd).cwiseAbs().maxCoeff() / Kd.cwiseAbs().maxCoeff();
    d.f = (f - f_ref).cwiseAbs().maxCoeff() / f_ref.cwiseAbs().maxCoeff();
    d.kv = (kv_r - kv_ref).cwiseAbs().maxCoeff() / kv_ref.cwiseAbs().maxCoeff();
    return d;
}

mesh::BoxGrid grid() {
    mesh::BoxGrid g;
    g.hi = Vec3(0.1, 0.06, 0.05);
    g.cells = { 6, 4, 3 };
    return g;
}

/// Nodes at x = 0 fixed, and one more node fixed in y only (its cells take the P1 kernel's full
/// scatter, the others the compact one).
std::vector<std::uint8_t> fixed_dofs(const mesh::Mesh& m) {
    std::vector<std::uint8_t> fixed(3 * m.rest.size(), 0);
    for (std::size_t i = 0; i < m.rest.size(); ++i)
        if (m.rest[i].x() < 1e-9)
            fixed[3 * i] = fixed[3 * i + 1] = fixed[3 * i + 2] = 1;
    fixed[3 * (m.rest.size() / 2) + 1] = 1;
    return fixed;
}

} // namespace

// The kernels scale the same blocks and multiply them with the same velocities: equal up to the
// order of sums (1e-13 of the largest entry; a wrong scale, a missing block or a transposed
// product is off by O(1)).
TEST(AssembleStep, EqualsTheScaledStiffnessAndItsProductWithTheVelocities) {
    const mesh::BoxGrid g = grid();
    const struct {
        const char* name;
        mesh::Mesh mesh;
    } meshes[] = {
        { "five-tet grid", mesh::tet_grid(g, mesh::TetSplit::Five) },
        { "Kuhn grid", mesh::tet_grid(g) },
        { "hex grid", mesh::hex_grid(g) },
        { "merged hexes", mesh::merged_hex_grid(g, 0.6, 3) },
    };
    for (const auto& [name, m] : meshes)
        for (int threads : { 1, 2 }) {
            const Difference d = compare(m, fixed_dofs(m), threads);
            EXPECT_LT(d.A, 1e-13) << name << ", " << threads << " threads";
            EXPECT_EQ(d.f, 0.0) << name << ", " << threads << " threads: the same forces";
            EXPECT_LT(d.kv, 1e-12) << name << ", " << threads << " threads";
        }
}

TEST(AssembleStep, TheNodalVolumetricTermIsRefusedAndNothingChanges) {
    const mesh::Mesh m = mesh::tet_grid(grid());
    basis::BasisOptions basis;
    basis.volumetric = basis::VolumetricRule::NodalAverage;
    Material mat;
    ElasticModel model(m, mat, basis, fixed_dofs(m));
    MatX3 x, v;
    deform(m, x, v);
    solve::SparseMatrix A = model.make_matrix();
    VecX f, kv;
    const VecX diagonal = VecX::Ones(model.num_free_dofs());
    EXPECT_FALSE(model.assemble_step(x, ForceMode::Corotated, 1.0, diagonal, v, A, f, kv));
    EXPECT_EQ(f.size(), 0);
    EXPECT_EQ(kv.size(), 0);
    EXPECT_EQ(Eigen::Map<const VecX>(A.valuePtr(), A.nonZeros()).cwiseAbs().maxCoeff(), 0.0);
}
