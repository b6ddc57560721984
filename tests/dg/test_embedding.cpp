// The surface of a DG field (issue 13 item 7, 003 sec. 8): stitching (003 eq. 17) and the MLS
// embedding (003 eq. 18-19).
// - An affine displacement is in every cell's space: stitched nodes and MLS points reproduce it
//   to round-off (MLS with a linear basis reproduces linear fields, 003 sec. 8).
// - A smooth (quadratic) deformation projected onto p = 1 cells is discontinuous: the crack a
//   surface would show if each cell drew its own field is measured per vertex; the stitched
//   surface has one position per vertex, so no crack, and its distance to the exact deformation
//   is bounded by the crack and shrinks as h^2.
// - The stitching's adjoint carries nodal forces to coefficient loads with the same work.
#include "dg_meshes.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/dg/embedding.hpp"
#include "polycut/dg/polynomial.hpp"
#include "polycut/mesh/builders.hpp"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <random>

using namespace polycut;
using namespace polycut::dg;

namespace {

elasticity::Material material() {
    elasticity::Material m;
    m.youngs_modulus = 1e4;
    m.poisson_ratio = 0.3;
    return m;
}

/// Generalised positions of the L2 projection of the displacement u(x) = q(x) e, q a
/// polynomial of degree 2 in global coordinates (graded monomials), onto the cells' bases:
/// coefficient i = int_K q phi_i / |K| (the basis is orthonormal with int phi_i phi_j = |K|).
MatX3 project(const DgModel& model, const VecX& q, const Vec3& e) {
    std::array<VecX, 3> comp;
    for (int a = 0; a < 3; ++a)
        comp[std::size_t(a)] = e[a] * q;
    const VecX F = model.polynomial_body_load(comp, 2);
    MatX3 x = model.rest();
    for (Index c = 0; c < model.num_cells(); ++c)
        for (int i = 0; i < model.basis(c).size(); ++i)
            for (int a = 0; a < 3; ++a)
                x(model.offset(c) + i, a) += F[dof(model.offset(c) + i, a)] / model.basis(c).volume;
    return x;
}

double quadratic(const VecX& q, const Vec3& X) {
    return q.dot(monomial_values(2, X));
}

} // namespace

TEST(DgEmbedding, AffineFieldsAreReproducedByStitchingAndMls) {
    for (const test::Kind kind : { test::Kind::Hex, test::Kind::Tet, test::Kind::Cut }) {
        const mesh::Mesh m = test::box_mesh(kind, 3);
        DgOptions o;
        o.degree = 1;
        const DgModel model(m, material(), o);
        const Mat3 G
            = (Mat3() << 0.01, 0.02, -0.03, 0.005, -0.01, 0.02, 0.03, 0.0, 0.01).finished();
        const Vec3 g0(0.1, -0.2, 0.05);
        // The affine map X -> X + g0 + G X is in every cell's span: x = X0 + u(X0 rows), since
        // the coefficients of a linear function of x are that function of the rest coefficients.
        MatX3 x = model.rest();
        for (Index c = 0; c < model.num_cells(); ++c) {
            const MatX3 X0 = model.rest().middleRows(model.offset(c), model.basis(c).size());
            for (int i = 0; i < model.basis(c).size(); ++i) {
                const Vec3 row = X0.row(i).transpose();
                x.row(model.offset(c) + i)
                    += (i == 0 ? Vec3(g0 + G * row) : Vec3(G * row)).transpose();
            }
        }
        const Stitching st(model);
        MatX3 u;
        st.displacements(x, u);
        double worst = 0;
        for (Index n = 0; n < m.num_nodes(); ++n)
            if (st.used(n))
                worst = std::max(
                    worst, (u.row(n).transpose() - (g0 + G * m.rest[std::size_t(n)])).norm());
        EXPECT_LT(worst, 1e-13) << test::name(kind);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> U(0.02, 0.98);
        std::vector<Vec3> points;
        for (int k = 0; k < 50; ++k)
            points.emplace_back(U(rng), U(rng), U(rng));
        points.emplace_back(1.0, 0.5, 0.5); // on the boundary
        const MlsEmbedding mls(model, points);
        MatX3 up;
        mls.displacements(u, up);
        double worst_mls = 0;
        for (std::size_t p = 0; p < points.size(); ++p)
            worst_mls
                = std::max(worst_mls, (up.row(Index(p)).transpose() - (g0 + G * points[p])).norm());
        EXPECT_LT(worst_mls, 1e-13) << test::name(kind);
    }
}

TEST(DgEmbedding, SmoothDeformationStitchedSurfaceHasNoCrackAndConvergesAsHSquared) {
    // u = 0.05 (x^2 + x y - 0.5 z^2 + 0.3 y) e, e = (0.3, -0.5, 0.8), projected onto p = 1.
    VecX q = VecX::Zero(num_monomials(2));
    q[monomial_index(2, 0, 0)] = 0.05;
    q[monomial_index(1, 1, 0)] = 0.05;
    q[monomial_index(0, 0, 2)] = -0.025;
    q[monomial_index(0, 1, 0)] = 0.015;
    const Vec3 e(0.3, -0.5, 0.8);
    double previous_error = 0, previous_crack = 0;
    for (const int n : { 4, 8 }) {
        const mesh::Mesh m = test::box_mesh(test::Kind::Hex, n);
        DgOptions o;
        o.degree = 1;
        const DgModel model(m, material(), o);
        const MatX3 x = project(model, q, e);
        // Crack: per boundary vertex, the largest distance between two cells' own values there.
        std::vector<std::vector<Vec3>> values(m.rest.size());
        for (Index c = 0; c < m.num_cells(); ++c)
            for (Index v : m.cells[std::size_t(c)].nodes)
                values[std::size_t(v)].push_back(model.displacement(x, c, m.rest[std::size_t(v)]));
        double crack = 0;
        for (const auto& vs : values)
            for (const Vec3& a : vs)
                for (const Vec3& b : vs)
                    crack = std::max(crack, (a - b).norm());
        const Stitching st(model);
        std::vector<Vec3> pos;
        st.positions(x, pos);
        double error = 0;
        for (Index v = 0; v < m.num_nodes(); ++v) {
            const Vec3& X = m.rest[std::size_t(v)];
            error = std::max(error, (pos[std::size_t(v)] - (X + quadratic(q, X) * e)).norm());
        }
        const double h = 1.0 / n;
        std::printf("[ info ] DG p=1 hex h=1/%d: per-vertex crack of the raw field %.3e m, "
                    "stitched surface error %.3e m (crack 0: one position per vertex)\n",
            n, crack, error);
        // Bound: on a cube of side h the L2 projection onto P1 misses a x^2 by a (h^2/6 - ...)
        // at a vertex (a h^2 / 6 at most) and a x y by (x - h/2)(y - h/2) (orthogonal to P1),
        // a h^2 / 4 at a vertex. So each cell's vertex error is at most
        // B = h^2 |e| (0.05/6 + 0.025/6 + 0.05/4); the crack between two cells is at most 2B and
        // the stitched average errs by at most B.
        const double B = h * h * e.norm() * (0.05 / 6 + 0.025 / 6 + 0.05 / 4);
        EXPECT_LE(crack, 2 * B * (1 + 1e-9));
        EXPECT_LE(error, B * (1 + 1e-9));
        EXPECT_GT(crack, 0.0); // the raw field does crack: stitching matters
        if (previous_error > 0) {
            EXPECT_GT(previous_error / error, 3.0); // O(h^2)
            EXPECT_GT(previous_crack / crack, 3.0);
        }
        previous_error = error;
        previous_crack = crack;
    }
}

TEST(DgEmbedding, StitchingAdjointPreservesWork) {
    const mesh::Mesh m = test::box_mesh(test::Kind::JitteredTet, 2);
    DgOptions o;
    o.degree = 2;
    const DgModel model(m, material(), o);
    const Stitching st(model);
    std::mt19937 rng(3);
    std::normal_distribution<double> N(0, 1);
    VecX f(3 * m.num_nodes());
    for (Index k = 0; k < f.size(); ++k)
        f[k] = N(rng);
    MatX3 x = model.rest();
    for (Index r = 0; r < x.rows(); ++r)
        x.row(r) += 1e-3 * Vec3(N(rng), N(rng), N(rng)).transpose();
    VecX load;
    st.loads(f, load);
    MatX3 u;
    st.displacements(x, u);
    const MatX3 du = x - model.rest();
    const double nodal_work = f.dot(flat(u));
    EXPECT_NEAR(load.dot(flat(du)), nodal_work, 1e-12 * std::abs(nodal_work));
}
