#include "polycut/quadrature/hex_rules.hpp"

#include "polycut/quadrature/gauss_jacobi.hpp"

namespace polycut::quadrature {

std::vector<RefPoint> hex_rule(int n) {
    const Rule1d g = gauss_legendre(n); // throws for n < 1
    std::vector<RefPoint> out;
    out.reserve(std::size_t(n * n * n));
    for (std::size_t k = 0; k < g.nodes.size(); ++k)
        for (std::size_t j = 0; j < g.nodes.size(); ++j)
            for (std::size_t i = 0; i < g.nodes.size(); ++i)
                out.push_back({ Vec3(g.nodes[i], g.nodes[j], g.nodes[k]),
                    g.weights[i] * g.weights[j] * g.weights[k] });
    return out;
}

} // namespace polycut::quadrature
