// Tensor-product Gauss-Legendre rules on the reference hexahedron [-1, 1]^3.
#pragma once

#include "polycut/common/types.hpp"

#include <vector>

namespace polycut::quadrature {

/// A point of a rule in reference coordinates; weights are in reference volume units.
struct RefPoint {
    Vec3 xi = Vec3::Zero(); ///< reference coordinates in [-1, 1]^3
    double weight = 0; ///< the weights of a hex rule sum to 8
};

/// n x n x n Gauss-Legendre points on [-1, 1]^3, exact for degree <= 2n - 1 in each variable;
/// n >= 1. Ordered with the x index fastest.
std::vector<RefPoint> hex_rule(int n);

} // namespace polycut::quadrature
