// Exactness of the quadrature rules against analytic monomial integrals.
#include "polycut/quadrature/gauss_jacobi.hpp"
#include "polycut/quadrature/hex_rules.hpp"
#include "polycut/quadrature/polyhedron_rule.hpp"
#include "polycut/quadrature/tet_rules.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::quadrature;

namespace {
double factorial(int n) {
    return std::tgamma(n + 1.0);
}

// Integral of x^a y^b z^c over the unit tet {x, y, z >= 0, x + y + z <= 1}: a! b! c! / (a+b+c+3)!.
double unit_tet_monomial(int a, int b, int c) {
    return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
}

double box_monomial(int a, int b, int c, const Vec3& lo, const Vec3& hi) {
    auto I = [](int e, double l, double h) {
        return (std::pow(h, e + 1) - std::pow(l, e + 1)) / (e + 1);
    };
    return I(a, lo.x(), hi.x()) * I(b, lo.y(), hi.y()) * I(c, lo.z(), hi.z());
}

double mono(const Vec3& p, int a, int b, int c) {
    return std::pow(p.x(), a) * std::pow(p.y(), b) * std::pow(p.z(), c);
}

double integrate_unit_tet(const std::vector<BaryPoint>& rule, int a, int b, int c) {
    double s = 0;
    for (const auto& q : rule) {
        const Vec3 p(q.bary[1], q.bary[2], q.bary[3]); // vertices 0, e1, e2, e3
        s += q.weight / 6.0 * mono(p, a, b, c);
    }
    return s;
}
} // namespace

TEST(GaussLegendre, ExactToDegree2nMinus1) {
    for (int n = 1; n <= 6; ++n) {
        const Rule1d r = gauss_legendre(n);
        for (int e = 0; e <= 2 * n - 1; ++e) {
            double s = 0;
            for (std::size_t k = 0; k < r.nodes.size(); ++k)
                s += r.weights[k] * std::pow(r.nodes[k], e);
            const double exact = (e % 2) ? 0.0 : 2.0 / (e + 1);
            EXPECT_NEAR(s, exact, 1e-14) << "n " << n << " e " << e;
        }
    }
}

TEST(TetRule, ExactForAllMonomialsUpToDegree) {
    for (int degree = 0; degree <= 7; ++degree) {
        const auto rule = tet_rule(degree);
        for (const auto& q : rule) {
            EXPECT_GT(q.weight, 0.0);
            for (double b : q.bary)
                EXPECT_GT(b, 0.0);
        }
        for (int a = 0; a <= degree; ++a)
            for (int b = 0; a + b <= degree; ++b)
                for (int c = 0; a + b + c <= degree; ++c)
                    EXPECT_NEAR(
                        integrate_unit_tet(rule, a, b, c), unit_tet_monomial(a, b, c), 1e-13)
                        << "degree " << degree << " monomial " << a << b << c;
    }
    EXPECT_EQ(tet_rule(1).size(), 1u);
    EXPECT_EQ(tet_rule(2).size(), 4u);
    EXPECT_EQ(tet_rule(5).size(), 27u);
}

TEST(TetRule, NotExactBeyondDegree) {
    // Sanity: the degree-2 rule must fail on some cubic (the test above could not fail otherwise).
    EXPECT_GT(
        std::abs(integrate_unit_tet(tet_rule(2), 3, 0, 0) - unit_tet_monomial(3, 0, 0)), 1e-6);
}

TEST(GrundmannMoeller, ExactForDegree2sPlus1) {
    const std::size_t expected_points[] = { 1, 5, 15, 35 };
    for (int s = 0; s <= 3; ++s) {
        const auto rule = grundmann_moeller_rule(s);
        EXPECT_EQ(rule.size(), expected_points[s]);
        const int degree = 2 * s + 1;
        for (int a = 0; a <= degree; ++a)
            for (int b = 0; a + b <= degree; ++b)
                for (int c = 0; a + b + c <= degree; ++c)
                    EXPECT_NEAR(
                        integrate_unit_tet(rule, a, b, c), unit_tet_monomial(a, b, c), 1e-13)
                        << "s " << s << " monomial " << a << b << c;
    }
}

TEST(HexRule, ExactForTensorMonomials) {
    for (int n = 1; n <= 4; ++n) {
        const auto rule = hex_rule(n);
        ASSERT_EQ(rule.size(), std::size_t(n * n * n));
        for (int a = 0; a <= 2 * n - 1; ++a)
            for (int b = 0; b <= 2 * n - 1; ++b)
                for (int c = 0; c <= 2 * n - 1; ++c) {
                    double s = 0;
                    for (const auto& q : rule)
                        s += q.weight * mono(q.xi, a, b, c);
                    EXPECT_NEAR(
                        s, box_monomial(a, b, c, Vec3::Constant(-1), Vec3::Constant(1)), 1e-13)
                        << "n " << n << " monomial " << a << b << c;
                }
    }
}

TEST(RuleOnTet, MapsToPhysicalTet) {
    const Vec3 a(0.1, 0.2, 0.3), b(1.3, 0.1, 0.2), c(0.2, 0.9, 0.1), d(0.4, 0.3, 1.1);
    const double vol = (b - a).dot((c - a).cross(d - a)) / 6.0;
    const auto rule = rule_on_tet(a, b, c, d, 3);
    double w = 0;
    Vec3 m = Vec3::Zero();
    for (const auto& q : rule) {
        w += q.weight;
        m += q.weight * q.point;
    }
    EXPECT_NEAR(w, vol, 1e-14);
    EXPECT_LT((m / w - (a + b + c + d) / 4.0).norm(), 1e-14);
}

namespace {
// Box [lo, hi] as 8 points and 6 outward quads (VTK hex numbering).
void box_loops(
    const Vec3& lo, const Vec3& hi, std::vector<Vec3>& P, std::vector<std::vector<Index>>& L) {
    P = { { lo.x(), lo.y(), lo.z() }, { hi.x(), lo.y(), lo.z() }, { hi.x(), hi.y(), lo.z() },
        { lo.x(), hi.y(), lo.z() }, { lo.x(), lo.y(), hi.z() }, { hi.x(), lo.y(), hi.z() },
        { hi.x(), hi.y(), hi.z() }, { lo.x(), hi.y(), hi.z() } };
    L = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 },
        { 3, 0, 4, 7 } };
}

double integrate(const std::vector<QuadPoint>& rule, int a, int b, int c) {
    double s = 0;
    for (const auto& q : rule)
        s += q.weight * mono(q.point, a, b, c);
    return s;
}
} // namespace

TEST(RuleOnPolyhedron, BoxMonomials) {
    const Vec3 lo(0.2, -0.3, 0.1), hi(1.0, 0.5, 0.6);
    std::vector<Vec3> P;
    std::vector<std::vector<Index>> L;
    box_loops(lo, hi, P, L);
    for (int degree = 1; degree <= 5; ++degree) {
        const auto rule = rule_on_polyhedron(P, L, degree);
        for (int a = 0; a <= degree; ++a)
            for (int b = 0; a + b <= degree; ++b)
                for (int c = 0; a + b + c <= degree; ++c) {
                    const double exact = box_monomial(a, b, c, lo, hi);
                    EXPECT_NEAR(
                        integrate(rule, a, b, c), exact, 1e-13 * std::max(1.0, std::abs(exact)))
                        << "degree " << degree << " monomial " << a << b << c;
                }
    }
}

TEST(RuleOnPolyhedron, NonConvexLPrism) {
    // L-shaped polygon in the xy plane (non-convex hexagon) extruded over z in [0, h]:
    // the union of [0,2]x[0,1] and [0,1]x[1,2].
    const double h = 0.7;
    const std::vector<Vec3> base
        = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 1, 0 }, { 1, 1, 0 }, { 1, 2, 0 }, { 0, 2, 0 } };
    std::vector<Vec3> P = base;
    for (const auto& p : base)
        P.push_back(p + Vec3(0, 0, h));
    std::vector<std::vector<Index>> L;
    L.push_back({ 5, 4, 3, 2, 1, 0 }); // bottom, outward -z
    L.push_back({ 6, 7, 8, 9, 10, 11 }); // top
    for (Index i = 0; i < 6; ++i) {
        const Index j = (i + 1) % 6;
        L.push_back({ i, j, Index(j + 6), Index(i + 6) });
    }
    // The L-hexagon fanned around its area centroid (5/6, 5/6) is star-shaped w.r.t. it.
    for (int degree = 1; degree <= 4; ++degree) {
        const auto rule = rule_on_polyhedron(P, L, degree);
        for (int a = 0; a <= degree; ++a)
            for (int b = 0; a + b <= degree; ++b)
                for (int c = 0; a + b + c <= degree; ++c) {
                    const double exact = box_monomial(a, b, c, Vec3(0, 0, 0), Vec3(2, 1, h))
                        + box_monomial(a, b, c, Vec3(0, 1, 0), Vec3(1, 2, h));
                    EXPECT_NEAR(
                        integrate(rule, a, b, c), exact, 1e-13 * std::max(1.0, std::abs(exact)))
                        << "degree " << degree << " monomial " << a << b << c;
                }
    }
}
