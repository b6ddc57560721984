// A UV sphere, the detailed surface of the embedding tests.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace polycut::test {

/// A UV sphere of `radius` about `c`: (rings - 1) * segments + 2 vertices.
inline void uv_sphere(const Vec3& c, double radius, int rings, int segments, std::vector<Vec3>& v,
    std::vector<std::array<Index, 3>>& t) {
    constexpr double pi = 3.14159265358979323846;
    v.push_back(c + Vec3(0, 0, radius));
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double th = pi * i / rings, ph = 2 * pi * j / segments;
            v.push_back(c
                + radius
                    * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
        }
    v.push_back(c - Vec3(0, 0, radius));
    const Index south = Index(v.size() - 1);
    auto ring = [&](int i, int j) { return Index(1 + (i - 1) * segments + (j % segments)); };
    for (int j = 0; j < segments; ++j) {
        t.push_back({ 0, ring(1, j), ring(1, j + 1) });
        t.push_back({ south, ring(rings - 1, j + 1), ring(rings - 1, j) });
        for (int i = 1; i + 1 < rings; ++i) {
            t.push_back({ ring(i, j), ring(i + 1, j), ring(i + 1, j + 1) });
            t.push_back({ ring(i, j), ring(i + 1, j + 1), ring(i, j + 1) });
        }
    }
}

} // namespace polycut::test
