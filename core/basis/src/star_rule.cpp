// Star tetrahedralization rules for polyhedral cells (see star_rule.hpp).
#include "star_rule.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <numbers>

namespace polycut::basis::detail {
namespace {
// n-point Gauss-Legendre rule on [0, 1] by Newton iteration on P_n.
void gauss_legendre_01(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(std::size_t(n), 0.0);
    w.assign(std::size_t(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
        double dp = 1;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) {
                p1 = z;
                p0 = 1;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16)
                break;
        }
        x[std::size_t(i)] = 0.5 * (1 - z);
        w[std::size_t(i)] = 1.0 / ((1 - z * z) * dp * dp);
    }
}

std::vector<TetPoint> make_rule(int degree) {
    if (degree <= 1)
        return { TetPoint { { 0.25, 0.25, 0.25, 0.25 }, 1.0 } };
    if (degree == 2) {
        const double a = 0.5854101966249685, b = 0.1381966011250105;
        return { TetPoint { { a, b, b, b }, 0.25 }, TetPoint { { b, a, b, b }, 0.25 },
            TetPoint { { b, b, a, b }, 0.25 }, TetPoint { { b, b, b, a }, 0.25 } };
    }
    // Duffy map of the unit cube onto the unit tet: z = c, y = b (1 - c),
    // x = a (1 - b) (1 - c), Jacobian (1 - b) (1 - c)^2 (adds degree 1 in b, 2 in c).
    const int n = (degree + 4) / 2;
    std::vector<double> t, w;
    gauss_legendre_01(n, t, w);
    std::vector<TetPoint> rule;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const double a = t[std::size_t(i)], b = t[std::size_t(j)], c = t[std::size_t(k)];
                const double z = c, y = b * (1 - c), x = a * (1 - b) * (1 - c);
                const double wt = 6.0 * w[std::size_t(i)] * w[std::size_t(j)] * w[std::size_t(k)]
                    * (1 - b) * (1 - c) * (1 - c);
                rule.push_back(TetPoint { { 1 - x - y - z, x, y, z }, wt });
            }
    return rule;
}
} // namespace

const std::vector<TetPoint>& tet_rule(int degree) {
    if (degree < 0 || degree > 30)
        throw InputError("/gauss_degree", "tet rule degree must be in [0, 30]");
    static std::mutex mutex;
    static std::map<int, std::vector<TetPoint>> cache;
    std::lock_guard lock(mutex);
    auto it = cache.find(degree);
    if (it == cache.end())
        it = cache.emplace(degree, make_rule(degree)).first;
    return it->second;
}

void star_rule(const std::vector<Vec3>& nodes, const std::vector<std::array<Index, 3>>& triangles,
    const Vec3& apex, int degree, std::vector<Vec3>& points, std::vector<double>& weights) {
    const auto& rule = tet_rule(degree);
    for (const auto& t : triangles) {
        const Vec3& a = nodes[std::size_t(t[0])];
        const Vec3& b = nodes[std::size_t(t[1])];
        const Vec3& c = nodes[std::size_t(t[2])];
        const double vol = (a - apex).dot((b - apex).cross(c - apex)) / 6.0;
        if (vol == 0.0)
            continue;
        for (const auto& q : rule) {
            points.push_back(q.bary[0] * apex + q.bary[1] * a + q.bary[2] * b + q.bary[3] * c);
            weights.push_back(q.weight * vol);
        }
    }
}

} // namespace polycut::basis::detail
