#include "polycut/quadrature/tet_rules.hpp"

#include "polycut/common/error.hpp"
#include "polycut/quadrature/gauss_jacobi.hpp"

#include <cmath>
#include <functional>

namespace polycut::quadrature {

std::vector<BaryPoint> tet_rule(int degree) {
    if (degree < 0)
        throw InputError("degree", "a quadrature degree must be >= 0");
    if (degree <= 1)
        return { BaryPoint { { 0.25, 0.25, 0.25, 0.25 }, 1.0 } };
    if (degree == 2) {
        // a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20.
        const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
        const double b = (5.0 - std::sqrt(5.0)) / 20.0;
        return { BaryPoint { { a, b, b, b }, 0.25 }, BaryPoint { { b, a, b, b }, 0.25 },
            BaryPoint { { b, b, a, b }, 0.25 }, BaryPoint { { b, b, b, a }, 0.25 } };
    }
    // Collapsed cube: x = u, y = (1 - u) v, z = (1 - u)(1 - v) w on the unit tet (volume 1/6),
    // Jacobian (1 - u)^2 (1 - v). A polynomial of total degree d in (x, y, z) has degree <= d in
    // each of u, v, w, so n = ceil((d + 1) / 2) Gauss points per axis suffice.
    const int n = (degree + 2) / 2;
    const Rule1d ru = gauss_jacobi_01(n, 2.0);
    const Rule1d rv = gauss_jacobi_01(n, 1.0);
    const Rule1d rw = gauss_jacobi_01(n, 0.0);
    std::vector<BaryPoint> out;
    out.reserve(std::size_t(n * n * n));
    for (std::size_t i = 0; i < ru.nodes.size(); ++i)
        for (std::size_t j = 0; j < rv.nodes.size(); ++j)
            for (std::size_t k = 0; k < rw.nodes.size(); ++k) {
                const double u = ru.nodes[i], v = rv.nodes[j], w = rw.nodes[k];
                const double x = u, y = (1 - u) * v, z = (1 - u) * (1 - v) * w;
                BaryPoint p;
                p.bary = { 1.0 - x - y - z, x, y, z };
                p.weight = 6.0 * ru.weights[i] * rv.weights[j] * rw.weights[k];
                out.push_back(p);
            }
    return out;
}

std::vector<BaryPoint> grundmann_moeller_rule(int s) {
    if (s < 0)
        throw InputError("s", "the Grundmann-Moeller index must be >= 0");
    constexpr int n = 3; // dimension
    const int d = 2 * s + 1;
    std::vector<BaryPoint> out;
    // GM Theorem 4: integral over the unit simplex (volume 1/n!) ~ sum_{i=0}^{s} (-1)^i 2^-2s
    // (d + n - 2i)^d / (i! (d + n - i)!) sum_{|beta| = s - i} f((2 beta + 1) / (d + n - 2i)).
    for (int i = 0; i <= s; ++i) {
        const double denom = d + n - 2 * i;
        const double log_w = -2.0 * s * std::log(2.0) + d * std::log(denom) - std::lgamma(i + 1.0)
            - std::lgamma(double(d + n - i) + 1.0);
        const double w = ((i % 2) ? -1.0 : 1.0) * std::exp(log_w) * 6.0; // fraction of volume
        const int m = s - i;
        for (int b0 = 0; b0 <= m; ++b0)
            for (int b1 = 0; b1 <= m - b0; ++b1)
                for (int b2 = 0; b2 <= m - b0 - b1; ++b2) {
                    const int b3 = m - b0 - b1 - b2;
                    BaryPoint p;
                    p.bary = { (2 * b0 + 1) / denom, (2 * b1 + 1) / denom, (2 * b2 + 1) / denom,
                        (2 * b3 + 1) / denom };
                    p.weight = w;
                    out.push_back(p);
                }
    }
    return out;
}

} // namespace polycut::quadrature
