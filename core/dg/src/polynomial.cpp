// Graded monomial tables and the polynomial algebra of polynomial.hpp.
#include "polycut/dg/polynomial.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace polycut::dg {
namespace {
struct Tables {
    std::vector<std::array<int, 3>> exponents;
    std::vector<int> index; // (kMaxDegree + 1)^3, -1 where a + b + c > kMaxDegree
    Tables() {
        constexpr int n = kMaxDegree + 1;
        index.assign(std::size_t(n * n * n), -1);
        for (int q = 0; q <= kMaxDegree; ++q)
            for (int a = q; a >= 0; --a)
                for (int b = q - a; b >= 0; --b) {
                    const int c = q - a - b;
                    index[std::size_t((a * n + b) * n + c)] = int(exponents.size());
                    exponents.push_back({ a, b, c });
                }
    }
};

const Tables& tables() {
    static const Tables t;
    return t;
}

void check_degree(int d, const char* what) {
    if (d < 0 || d > kMaxDegree)
        throw InputError(what,
            "polynomial degree " + std::to_string(d) + " outside [0, " + std::to_string(kMaxDegree)
                + "]");
}

/// Binomial coefficients C(n, k) for n <= kMaxDegree.
double binomial(int n, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i)
        r = r * double(n - k + i) / double(i);
    return r;
}
} // namespace

const std::array<int, 3>& exponent(int k) {
    return tables().exponents[std::size_t(k)];
}

int monomial_index(int a, int b, int c) {
    if (a < 0 || b < 0 || c < 0 || a + b + c > kMaxDegree)
        return -1;
    constexpr int n = kMaxDegree + 1;
    return tables().index[std::size_t((a * n + b) * n + c)];
}

VecX monomial_values(int d, const Vec3& xi) {
    check_degree(d, "degree");
    VecX v(num_monomials(d));
    for (int k = 0; k < v.size(); ++k) {
        const auto& e = exponent(k);
        double m = 1;
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 0; i < e[std::size_t(axis)]; ++i)
                m *= xi[axis];
        v[k] = m;
    }
    return v;
}

VecX multiply(const VecX& p, int dp, const VecX& q, int dq) {
    check_degree(dp + dq, "degree");
    VecX r = VecX::Zero(num_monomials(dp + dq));
    for (int i = 0; i < p.size(); ++i) {
        if (p[i] == 0)
            continue;
        const auto& a = exponent(i);
        for (int j = 0; j < q.size(); ++j) {
            const auto& b = exponent(j);
            r[monomial_index(a[0] + b[0], a[1] + b[1], a[2] + b[2])] += p[i] * q[j];
        }
    }
    return r;
}

MatX derivative_matrix(int d, int axis) {
    check_degree(d, "degree");
    MatX D = MatX::Zero(num_monomials(d), num_monomials(d - 1));
    for (int k = 0; k < D.rows(); ++k) {
        auto e = exponent(k);
        const int power = e[std::size_t(axis)];
        if (power == 0)
            continue;
        e[std::size_t(axis)] -= 1;
        D(k, monomial_index(e[0], e[1], e[2])) = power;
    }
    return D;
}

MatX rebase_matrix(int d, const Vec3& shift, double scale) {
    check_degree(d, "degree");
    // (shift_k + scale zeta_k)^n = sum_m C(n, m) shift_k^(n - m) scale^m zeta_k^m, per axis.
    const int n = num_monomials(d);
    MatX R = MatX::Zero(n, n);
    std::array<std::vector<std::vector<double>>, 3> axis_terms; // [axis][n][m]
    for (int axis = 0; axis < 3; ++axis) {
        auto& t = axis_terms[std::size_t(axis)];
        t.assign(std::size_t(d + 1), std::vector<double>(std::size_t(d + 1), 0.0));
        for (int p = 0; p <= d; ++p)
            for (int m = 0; m <= p; ++m)
                t[std::size_t(p)][std::size_t(m)]
                    = binomial(p, m) * std::pow(shift[axis], p - m) * std::pow(scale, m);
    }
    for (int k = 0; k < n; ++k) {
        const auto& e = exponent(k);
        for (int i = 0; i <= e[0]; ++i)
            for (int j = 0; j <= e[1]; ++j)
                for (int l = 0; l <= e[2]; ++l)
                    R(k, monomial_index(i, j, l))
                        += axis_terms[0][std::size_t(e[0])][std::size_t(i)]
                        * axis_terms[1][std::size_t(e[1])][std::size_t(j)]
                        * axis_terms[2][std::size_t(e[2])][std::size_t(l)];
    }
    return R;
}

MatX monomial_gram(const VecX& moments, int d) {
    const int n = num_monomials(d);
    if (moments.size() < num_monomials(2 * d))
        throw InputError("moments",
            "Gram matrix of degree " + std::to_string(d) + " needs moments of degree "
                + std::to_string(2 * d));
    MatX G(n, n);
    for (int r = 0; r < n; ++r)
        for (int s = 0; s <= r; ++s) {
            const auto& a = exponent(r);
            const auto& b = exponent(s);
            G(r, s) = G(s, r) = moments[monomial_index(a[0] + b[0], a[1] + b[1], a[2] + b[2])];
        }
    return G;
}

} // namespace polycut::dg
