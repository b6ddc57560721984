// Exact polyhedral integration (issue 13 item 2): monomial moments by the divergence theorem
// against closed forms on boxes, a tetrahedron and an L-shaped (non-convex) prism, to 1e-14.
#include "polycut/dg/polyhedron_moments.hpp"
#include "polycut/dg/polynomial.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::dg;

namespace {
/// int_lo^hi ((x - o) / s)^a dx
double line_moment(double lo, double hi, double o, double s, int a) {
    return s / (a + 1) * (std::pow((hi - o) / s, a + 1) - std::pow((lo - o) / s, a + 1));
}

struct Box {
    Vec3 lo, hi;
};

/// Box as 8 points and 6 outward loops, appended to points/loops.
void add_box(const Box& b, std::vector<Vec3>& points, std::vector<std::vector<Index>>& loops) {
    const Index base = Index(points.size());
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                points.emplace_back(
                    i ? b.hi.x() : b.lo.x(), j ? b.hi.y() : b.lo.y(), k ? b.hi.z() : b.lo.z());
    auto v = [&](int i, int j, int k) { return base + Index(i + 2 * j + 4 * k); };
    loops.push_back({ v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0) }); // z-
    loops.push_back({ v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1) }); // z+
    loops.push_back({ v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1) }); // y-
    loops.push_back({ v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0) }); // y+
    loops.push_back({ v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0) }); // x-
    loops.push_back({ v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1) }); // x+
}

double box_moment(const Box& b, const Vec3& o, double s, int k) {
    const auto& e = exponent(k);
    double r = 1;
    for (int a = 0; a < 3; ++a)
        r *= line_moment(b.lo[a], b.hi[a], o[a], s, e[std::size_t(a)]);
    return r;
}

double factorial(int n) {
    return n <= 1 ? 1.0 : n * factorial(n - 1);
}
} // namespace

TEST(DgMoments, BoxesToRoundOffAtEveryDegree) {
    const Box boxes[]
        = { { Vec3(0, 0, 0), Vec3(1, 1, 1) }, { Vec3(-0.3, 0.1, 2), Vec3(0.4, 2.5, 2.2) },
              { Vec3(100, 100, 100), Vec3(100.01, 100.02, 100.005) } };
    for (const Box& b : boxes) {
        std::vector<Vec3> points;
        std::vector<std::vector<Index>> loops;
        add_box(b, points, loops);
        const Vec3 o = 0.5 * (b.lo + b.hi) + 0.1 * (b.hi - b.lo);
        const double s = (b.hi - b.lo).norm();
        const VecX M = polyhedron_moments(points, loops, o, s, 8);
        const double volume = (b.hi - b.lo).prod();
        for (int k = 0; k < M.size(); ++k)
            EXPECT_NEAR(M[k], box_moment(b, o, s, k), 1e-14 * volume) << "monomial " << k;
    }
}

TEST(DgMoments, TetrahedronMatchesTheDirichletFormula) {
    // int over the unit simplex of x^a y^b z^c = a! b! c! / (a + b + c + 3)!
    const std::vector<Vec3> points { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
    const std::vector<std::vector<Index>> loops { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 },
        { 0, 3, 2 } };
    const VecX M = polyhedron_moments(points, loops, Vec3::Zero(), 1.0, 10);
    for (int k = 0; k < M.size(); ++k) {
        const auto& e = exponent(k);
        const double exact = factorial(e[0]) * factorial(e[1]) * factorial(e[2])
            / factorial(e[0] + e[1] + e[2] + 3);
        EXPECT_NEAR(M[k], exact, 1e-14 * exact + 1e-17) << "monomial " << k;
    }
}

TEST(DgMoments, NonConvexLShapedPrismEqualsItsTwoBoxes) {
    // L in the xy-plane: [0,2]x[0,1] + [0,1]x[1,2], extruded over z in [0, 0.5]: one cell with
    // a non-convex 6-gon top and bottom.
    std::vector<Vec3> points;
    const double xy[6][2] = { { 0, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1, 2 }, { 0, 2 } };
    for (double z : { 0.0, 0.5 })
        for (const auto& p : xy)
            points.emplace_back(p[0], p[1], z);
    std::vector<std::vector<Index>> loops { { 5, 4, 3, 2, 1, 0 }, { 6, 7, 8, 9, 10, 11 } };
    for (Index i = 0; i < 6; ++i)
        loops.push_back({ i, Index((i + 1) % 6), Index((i + 1) % 6 + 6), Index(i + 6) });
    const Vec3 o(0.7, 0.7, 0.25);
    const VecX M = polyhedron_moments(points, loops, o, 2.0, 8);
    const Box a { Vec3(0, 0, 0), Vec3(2, 1, 0.5) }, b { Vec3(0, 1, 0), Vec3(1, 2, 0.5) };
    for (int k = 0; k < M.size(); ++k)
        EXPECT_NEAR(M[k], box_moment(a, o, 2.0, k) + box_moment(b, o, 2.0, k), 1e-14 * 1.5)
            << "monomial " << k;
    // The same L as a face: polygon moments of the bottom.
    const VecX F = polygon_moments(points, loops[0], o, 2.0, 6);
    for (int k = 0; k < F.size(); ++k) {
        const auto& e = exponent(k);
        // The bottom lies on z = 0, where ((z - o_z) / 2)^c is a constant.
        const double exact
            = (line_moment(0, 2, o.x(), 2, e[0]) * line_moment(0, 1, o.y(), 2, e[1])
                  + line_moment(0, 1, o.x(), 2, e[0]) * line_moment(1, 2, o.y(), 2, e[1]))
            * std::pow((0 - o.z()) / 2, e[2]);
        EXPECT_NEAR(F[k], exact, 1e-14 * 3) << "monomial " << k;
    }
}

TEST(DgMoments, PolynomialAlgebraIsConsistent) {
    // Rebase then evaluate == evaluate at the mapped point; derivative by finite difference.
    const Vec3 shift(0.3, -0.2, 0.5);
    const double scale = 0.7;
    const MatX R = rebase_matrix(3, shift, scale);
    VecX p(num_monomials(3));
    for (int k = 0; k < p.size(); ++k)
        p[k] = std::sin(1.0 + k);
    const Vec3 zeta(0.2, 0.9, -0.4);
    const double direct = p.dot(monomial_values(3, shift + scale * zeta));
    const double rebased = (p.transpose() * R).dot(monomial_values(3, zeta).transpose());
    EXPECT_NEAR(direct, rebased, 1e-13);
    const VecX dp = (p.transpose() * derivative_matrix(3, 1)).transpose();
    const double h = 1e-6;
    const double fd = (p.dot(monomial_values(3, zeta + Vec3(0, h, 0)))
                          - p.dot(monomial_values(3, zeta - Vec3(0, h, 0))))
        / (2 * h);
    EXPECT_NEAR(dp.dot(monomial_values(2, zeta)), fd, 1e-7);
    const VecX q = multiply(p, 3, dp, 2);
    EXPECT_NEAR(q.dot(monomial_values(5, zeta)),
        p.dot(monomial_values(3, zeta)) * dp.dot(monomial_values(2, zeta)), 1e-12);
}

TEST(DgMoments, TiltedQuadEqualsItsTwoTriangles) {
    const std::vector<Vec3> points { Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1.2, 1.1, 1),
        Vec3(0.1, 0.05, 1.3) };
    // Make it planar: the fourth point in the plane of the first three.
    std::vector<Vec3> p = points;
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    p[3] -= n * n.dot(p[3] - p[0]);
    const std::vector<Index> quad { 0, 1, 2, 3 }, t1 { 0, 1, 2 }, t2 { 0, 2, 3 };
    const Vec3 o(0.5, 0.5, 0.6);
    const VecX q = polygon_moments(p, quad, o, 1.5, 6);
    const VecX s = polygon_moments(p, t1, o, 1.5, 6) + polygon_moments(p, t2, o, 1.5, 6);
    EXPECT_LT((q - s).lpNorm<Eigen::Infinity>(), 1e-14);
}
