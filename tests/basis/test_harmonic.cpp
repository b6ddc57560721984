// Harmonic basis by the method of fundamental solutions (seed 001 sec. 4-5): exact partition of
// unity and linear precision, P1 on tets, close to Q1 on boxes, boundary and inter-cell (C0)
// errors against the paper's 2-3 %, gradients against finite differences, rigid modes of Ke,
// the patch test, non-convex cells and merged coincident nodes.
#include "polycut/basis/harmonic.hpp"
#include "polyhedral_cells.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <random>

namespace polycut::basis {
namespace {
using namespace testing;

struct Named {
    const char* name;
    CellGeometry cell;
};

std::vector<Named> cells() {
    auto split = slanted_split_hex();
    return { { "tet", unit_tet() }, { "cube", cube() }, { "cut_cube", cut_cube() },
        { "split_lower", split.cells[0] }, { "split_upper", split.cells[1] },
        { "truncated_octahedron", truncated_octahedron() }, { "l_prism", l_prism() } };
}

/// Random points inside the cell: rejection sampling in the box against the Gauss points'
/// star tets is overkill; use random points of the reference rule's tets instead.
std::vector<Vec3> interior_points(const HarmonicCell& cell, int count, unsigned seed) {
    const auto ci = cell.integrate({ HarmonicRule::MonteCarlo, 0, count, seed });
    return ci.points;
}

/// Triangle rule (Duffy-collapsed Gauss-Legendre, n x n points) on the unit triangle:
/// barycentric (1 - s - t, s, t) and weights summing to 1.
std::vector<std::pair<Vec3, double>> triangle_rule(int n) {
    const auto count = std::size_t(n);
    std::vector<double> x(count), w(count);
    // Golub-Welsch for Legendre on [-1, 1]
    MatX J = MatX::Zero(n, n);
    for (int k = 1; k < n; ++k)
        J(k, k - 1) = J(k - 1, k) = k / std::sqrt(4.0 * k * k - 1);
    Eigen::SelfAdjointEigenSolver<MatX> es(J);
    for (int k = 0; k < n; ++k) {
        x[std::size_t(k)] = 0.5 * (1 + es.eigenvalues()[k]);
        w[std::size_t(k)] = std::pow(es.eigenvectors()(0, k), 2); // sums to 1 on [0, 1]
    }
    std::vector<std::pair<Vec3, double>> out;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double a = x[std::size_t(i)], b = x[std::size_t(j)];
            const double s = a * (1 - b), t = b;
            out.push_back(
                { Vec3(1 - s - t, s, t), 2.0 * w[std::size_t(i)] * w[std::size_t(j)] * (1 - b) });
        }
    return out;
}

/// int over the cell surface of N_i sigma n dA (#n x 3) for a constant stress S, with the
/// cell's own 3D functions, by a high-order triangle rule on a fan of each face.
MatX3 boundary_forces(const HarmonicCell& cell, const CellGeometry& geo, const Mat3& S) {
    const auto rule = triangle_rule(12);
    MatX3 f = MatX3::Zero(cell.num_nodes(), 3);
    VecX phi;
    for (const auto& loop : geo.loops)
        for (std::size_t s = 1; s + 1 < loop.size(); ++s) {
            const Vec3& a = geo.nodes[std::size_t(loop[0])];
            const Vec3& b = geo.nodes[std::size_t(loop[s])];
            const Vec3& c = geo.nodes[std::size_t(loop[s + 1])];
            const Vec3 an = 0.5 * (b - a).cross(c - a);
            for (const auto& [bary, w] : rule) {
                cell.evaluate(bary[0] * a + bary[1] * b + bary[2] * c, phi);
                f += w * phi * (S * an).transpose();
            }
        }
    return f;
}

Mat3 test_gradient() {
    Mat3 G;
    G << 0.01, 0.003, -0.002, 0.004, -0.02, 0.005, 0.001, 0.006, 0.015;
    return G;
}
} // namespace

TEST(Harmonic, PartitionOfUnityAndExactLinearPrecision) {
    for (const auto& [name, geo] : cells()) {
        SCOPED_TRACE(name);
        const HarmonicCell cell(geo);
        const double h = cell.size();
        VecX phi;
        MatX3 grad;
        double worst_val = 0, worst_grad = 0;
        for (const Vec3& x : interior_points(cell, 100, 1)) {
            cell.evaluate(x, phi, &grad);
            Vec3 rep = Vec3::Zero();
            Mat3 grep = Mat3::Zero();
            for (Index i = 0; i < cell.num_nodes(); ++i) {
                rep += phi[i] * geo.nodes[std::size_t(i)];
                grep += geo.nodes[std::size_t(i)] * grad.row(i);
            }
            worst_val = std::max({ worst_val, std::abs(phi.sum() - 1), (rep - x).norm() / h });
            worst_grad = std::max(
                { worst_grad, (grep - Mat3::Identity()).norm(), grad.colwise().sum().norm() * h });
        }
        // 001 sec. 5: the linear term makes reproduction exact, independent of the kernels
        EXPECT_LT(worst_val, 1e-12);
        EXPECT_LT(worst_grad, 1e-11);
    }
}

TEST(Harmonic, TetIsP1) {
    const auto geo = unit_tet();
    const HarmonicCell cell(geo);
    Eigen::Matrix4d A;
    for (int i = 0; i < 4; ++i)
        A.col(i) << geo.nodes[std::size_t(i)], 1.0;
    const Eigen::Matrix4d Ainv = A.inverse();
    VecX phi;
    MatX3 grad;
    for (const Vec3& x : interior_points(cell, 50, 3)) {
        cell.evaluate(x, phi, &grad);
        const Eigen::Vector4d bary = Ainv * Eigen::Vector4d(x.x(), x.y(), x.z(), 1.0);
        EXPECT_LT((phi - bary).norm(), 1e-11);
        EXPECT_LT((grad - Ainv.leftCols<3>()).norm(), 1e-10 * Ainv.norm());
    }
}

TEST(Harmonic, BoxIsCloseToQ1) {
    // Trilinear functions are harmonic, so on a box the exact harmonic basis is Q1 (001 sec. 4);
    // the MFS approximation must be close.
    const auto geo = cube(); // [0, 2] x [0, 1.5] x [0, 1]
    const HarmonicCell cell(geo);
    VecX phi;
    double worst = 0;
    for (const Vec3& x : interior_points(cell, 200, 5)) {
        cell.evaluate(x, phi);
        const Vec3 t(x.x() / 2, x.y() / 1.5, x.z());
        for (Index i = 0; i < cell.num_nodes(); ++i) {
            const Vec3& p = geo.nodes[std::size_t(i)];
            const double q = (p.x() > 0 ? t.x() : 1 - t.x()) * (p.y() > 0 ? t.y() : 1 - t.y())
                * (p.z() > 0 ? t.z() : 1 - t.z());
            worst = std::max(worst, std::abs(phi[i] - q));
        }
    }
    std::printf("harmonic vs Q1 on a box: max |N - Q1| = %.3e\n", worst);
    EXPECT_LT(worst, 0.02);
}

TEST(Harmonic, BoundaryErrorAndKroneckerDelta) {
    for (const auto& [name, geo] : cells()) {
        const HarmonicCell cell(geo);
        const auto err = cell.boundary_error();
        double delta = 0;
        VecX phi;
        for (Index i = 0; i < cell.num_nodes(); ++i) {
            cell.evaluate(geo.nodes[std::size_t(i)], phi);
            VecX e = VecX::Zero(cell.num_nodes());
            e[i] = 1;
            delta = std::max(delta, (phi - e).lpNorm<Eigen::Infinity>());
        }
        std::printf(
            "harmonic %-22s n=%3d m=%4d  boundary L2 %.3e  max %.3e  |N_i(x_j) - d_ij| %.3e\n",
            name, cell.num_kernels(), cell.num_collocation(), err.rms, err.max, delta);
        // 001 sec. 5: L2 boundary errors of about 2-3 % with 5 edge samples. The non-convex
        // L prism is worse near its re-entrant edge (the exact functions are singular there).
        const bool convex = std::string(name) != "l_prism";
        EXPECT_LT(err.rms, convex ? 0.03 : 0.06) << name;
        EXPECT_LT(err.max, convex ? 0.08 : 0.25) << name;
        EXPECT_LT(delta, convex ? 0.05 : 0.25) << name;
    }
}

TEST(Harmonic, NormalEquationsMatchQR) {
    // The default solver (Cholesky of the scaled normal equations + one refinement step) must
    // reach the least-squares solution of Householder QR: same boundary error to 1e-3 relative,
    // same functions to 1e-6.
    for (const auto& [name, geo] : cells()) {
        HarmonicOptions qr;
        qr.solver = HarmonicSolver::QR;
        const HarmonicCell fast(geo), ref(geo, qr);
        const auto ef = fast.boundary_error(), er = ref.boundary_error();
        EXPECT_LE(std::abs(ef.rms - er.rms), 1e-3 * er.rms + 1e-12) << name;
        VecX pf, pr;
        MatX3 gf, gr;
        for (const auto& x : interior_points(ref, 50, 3)) {
            fast.evaluate(x, pf, &gf);
            ref.evaluate(x, pr, &gr);
            EXPECT_LT((pf - pr).lpNorm<Eigen::Infinity>(), 1e-6) << name;
            EXPECT_LT((gf - gr).norm(), 1e-6 * gr.norm() / fast.size() + 1e-9) << name;
        }
    }
}

TEST(Harmonic, ApproximatelyContinuousAcrossASharedFace) {
    const auto g = slanted_split_hex();
    const HarmonicCell lower(g.cells[0]), upper(g.cells[1]);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    VecX pl, pu;
    double worst = 0, sum2 = 0;
    int count = 0;
    for (int k = 0; k < 300; ++k) {
        const double x = uni(rng), y = uni(rng);
        const Vec3 p(x, y, 0.3 + 0.4 * x);
        lower.evaluate(p, pl);
        upper.evaluate(p, pu);
        for (std::size_t c = 0; c < 2; ++c) {
            const VecX& mine = c == 0 ? pl : pu;
            const VecX& other = c == 0 ? pu : pl;
            for (std::size_t i = 0; i < g.cell_nodes[c].size(); ++i) {
                const Index j = local_of(g, 1 - c, g.cell_nodes[c][i]);
                const double o = std::size_t(j) < g.cell_nodes[1 - c].size() ? other[j] : 0.0;
                const double e = std::abs(mine[Eigen::Index(i)] - o);
                worst = std::max(worst, e);
                sum2 += e * e;
                ++count;
            }
        }
    }
    const double rms = std::sqrt(sum2 / count);
    std::printf("harmonic C0 mismatch on the shared face: rms %.3e  max %.3e\n", rms, worst);
    EXPECT_LT(rms, 0.02);
    EXPECT_LT(worst, 0.1);
}

TEST(Harmonic, GradientsMatchFiniteDifferences) {
    for (const auto& [name, geo] : cells()) {
        SCOPED_TRACE(name);
        const HarmonicCell cell(geo);
        const double h = 1e-6 * cell.size();
        VecX phi, pp, pm;
        MatX3 grad;
        for (const Vec3& x : interior_points(cell, 20, 2)) {
            cell.evaluate(x, phi, &grad);
            MatX3 fd(grad.rows(), 3);
            for (int k = 0; k < 3; ++k) {
                Vec3 dx = Vec3::Zero();
                dx[k] = h;
                cell.evaluate(x + dx, pp);
                cell.evaluate(x - dx, pm);
                fd.col(k) = (pp - pm) / (2 * h);
            }
            EXPECT_LT((fd - grad).norm(), 1e-6 * std::max(1.0, grad.norm()));
        }
    }
}

TEST(Harmonic, StiffnessIsSymmetricPsdWithSixRigidModes) {
    const auto C = isotropic_c(1.0, 0.3);
    for (const auto& [name, geo] : cells()) {
        SCOPED_TRACE(name);
        const HarmonicCell cell(geo);
        const auto ci = cell.integrate({ HarmonicRule::Gauss, 3 });
        double wsum = 0;
        for (double w : ci.weights) {
            EXPECT_GT(w, 0.0);
            wsum += w;
        }
        EXPECT_NEAR(wsum, cell.volume(), 1e-12 * cell.volume());
        EXPECT_NEAR(ci.lumped_volume.sum(), cell.volume(), 1e-11 * cell.volume());
        const MatX K = stiffness(ci, C);
        EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
        Eigen::SelfAdjointEigenSolver<MatX> es(0.5 * (K + K.transpose()));
        const VecX ev = es.eigenvalues();
        const double top = ev[ev.size() - 1];
        for (Eigen::Index k = 0; k < 6; ++k)
            EXPECT_LT(std::abs(ev[k]), 1e-11 * top) << "k=" << k;
        EXPECT_GT(ev[6], 1e-6 * top);
    }
}

TEST(Harmonic, PatchTestConvergesWithTheRule) {
    // K u for u = G x must equal the boundary forces int N_i sigma n dA of the same functions:
    // exact in the limit of the rule (the MFS functions are smooth inside the cell).
    const auto C = isotropic_c(1.0, 0.3);
    const Mat3 G = test_gradient();
    const Mat3 S = voigt_to_tensor(stress_of(G, C));
    for (const auto& [name, geo] : cells()) {
        const HarmonicCell cell(geo);
        const MatX3 fe = boundary_forces(cell, geo, S);
        MatX3 u(cell.num_nodes(), 3);
        for (Index i = 0; i < cell.num_nodes(); ++i)
            u.row(i) = (G * geo.nodes[std::size_t(i)]).transpose();
        std::printf("harmonic patch test %-22s", name);
        double first = 0, last = 0;
        for (int degree : { 1, 2, 4, 8 }) {
            const MatX K = stiffness(cell.integrate({ HarmonicRule::Gauss, degree }), C);
            const double err = (K * flat(u) - flat(fe)).norm() / flat(fe).norm();
            std::printf("  deg%d %.2e", degree, err);
            (degree == 1 ? first : last) = err;
        }
        const auto mc = cell.integrate({ HarmonicRule::MonteCarlo, 0, 20000, 7 });
        const double err_mc = (stiffness(mc, C) * flat(u) - flat(fe)).norm() / flat(fe).norm();
        std::printf("  monte-carlo(2e4) %.2e\n", err_mc);
        // kernels sit 0.1 size outside, so Gauss converges geometrically but slowly
        EXPECT_LT(last, 1e-3) << name;
        EXPECT_LT(last, 0.1 * first + 1e-12) << name;
        EXPECT_LT(err_mc, 0.2) << name;
    }
}

TEST(Harmonic, GluedPatchTest) {
    // Assembled over the two halves of the split hex, K u for a linear u must equal the forces
    // on the outer boundary; the interior face contributes the C0 mismatch of the two cells.
    const auto g = slanted_split_hex();
    const auto C = isotropic_c(1.0, 0.3);
    const Mat3 G = test_gradient();
    const Mat3 S = voigt_to_tensor(stress_of(G, C));
    const Index n = Index(g.nodes.size());
    MatX3 f = MatX3::Zero(n, 3), exact = MatX3::Zero(n, 3);
    for (std::size_t c = 0; c < g.cells.size(); ++c) {
        const HarmonicCell cell(g.cells[c]);
        const MatX K = stiffness(cell.integrate({ HarmonicRule::Gauss, 6 }), C);
        MatX3 u(cell.num_nodes(), 3);
        for (Index i = 0; i < cell.num_nodes(); ++i)
            u.row(i) = (G * g.cells[c].nodes[std::size_t(i)]).transpose();
        const VecX fc = K * flat(u);
        // exact outer-boundary forces: the cell's own trace on its cube faces
        CellGeometry outer = g.cells[c];
        outer.loops.clear();
        for (const auto& loop : g.cells[c].loops) {
            const Vec3& a = outer.nodes[std::size_t(loop[0])];
            const Vec3 nrm = (outer.nodes[std::size_t(loop[1])] - a)
                                 .cross(outer.nodes[std::size_t(loop[2])] - a)
                                 .normalized();
            if (std::abs(nrm.x()) + std::abs(nrm.y()) + std::abs(nrm.z()) < 1 + 1e-9)
                outer.loops.push_back(loop);
        }
        const MatX3 fe = boundary_forces(cell, outer, S);
        for (Index i = 0; i < cell.num_nodes(); ++i) {
            f.row(g.cell_nodes[c][std::size_t(i)]) += fc.segment<3>(3 * i).transpose();
            exact.row(g.cell_nodes[c][std::size_t(i)]) += fe.row(i);
        }
    }
    const double err = (flat(f) - flat(exact)).norm() / flat(exact).norm();
    std::printf("harmonic glued patch test (2 cells, degree 6): relative force error %.3e\n", err);
    EXPECT_LT(err, 0.05);
}

TEST(Harmonic, NonConvexCellIntegratesAndKernelsStayOutside) {
    const auto geo = l_prism();
    const HarmonicCell cell(geo);
    EXPECT_NEAR(cell.volume(), 3.0, 1e-14);
    const auto gauss = cell.integrate({ HarmonicRule::Gauss, 4 });
    double w = 0;
    for (double x : gauss.weights)
        w += x;
    EXPECT_NEAR(w, 3.0, 1e-12);
    // harmonic functions are bounded by their boundary data: no kernel inside the notch
    VecX phi;
    for (const Vec3& x : interior_points(cell, 300, 9)) {
        cell.evaluate(x, phi);
        EXPECT_GT(phi.minCoeff(), -0.05);
        EXPECT_LT(phi.maxCoeff(), 1.05);
    }
    // Monte Carlo against Gauss: lumped volumes agree to the sampling error
    const auto mc = cell.integrate({ HarmonicRule::MonteCarlo, 0, 20000, 3 });
    const double diff
        = (mc.lumped_volume - gauss.lumped_volume).norm() / gauss.lumped_volume.norm();
    std::printf("L prism lumped volumes, Monte Carlo (2e4) vs Gauss deg4: %.3e\n", diff);
    EXPECT_LT(diff, 0.03);
}

TEST(Harmonic, CoincidentNodesShareAJointFunction) {
    // A box whose corner 0 is doubled: node 8 sits on node 0 and follows it in every loop.
    auto geo = cube();
    const Index dup = Index(geo.nodes.size());
    geo.nodes.push_back(geo.nodes[0]);
    for (auto& loop : geo.loops) {
        const auto it = std::find(loop.begin(), loop.end(), 0);
        if (it != loop.end())
            loop.insert(it + 1, dup);
    }
    const HarmonicCell cell(geo);
    const HarmonicCell plain(cube());
    VecX phi, ref;
    for (const Vec3& x : interior_points(plain, 20, 11)) {
        cell.evaluate(x, phi);
        plain.evaluate(x, ref);
        EXPECT_NEAR(phi[0], phi[dup], 1e-15);
        EXPECT_NEAR(phi[0] + phi[dup], ref[0], 1e-9);
        EXPECT_NEAR(phi.sum(), 1.0, 1e-12);
    }
}

TEST(Harmonic, MeshWrapper) {
    const auto geo = l_prism();
    const auto mesh = mesh::Mesh::from_polyhedra(geo.nodes, { geo.loops });
    const auto ci = integrate_harmonic(mesh, 0);
    EXPECT_NEAR(ci.lumped_volume.sum(), 3.0, 1e-10);
    const auto& nodes = mesh.cells[0].nodes;
    Mat3 grep = Mat3::Zero();
    for (std::size_t i = 0; i < nodes.size(); ++i)
        grep += mesh.rest[std::size_t(nodes[i])] * ci.gradients[0].row(Index(i));
    EXPECT_LT((grep - Mat3::Identity()).norm(), 1e-11);
}

} // namespace polycut::basis
