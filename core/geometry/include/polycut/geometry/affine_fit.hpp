// Least-squares affine fit of a cell's deformation and its rotation (corotation, DESIGN.md
// sec. 1): x_i ~ A X_i + t over the cell's nodes; R is the rotation of the polar decomposition
// A = R S (000 sec. 3.6 uses Horn's registration; this is the same rotation).
#pragma once

#include "polycut/common/types.hpp"

#include <span>

namespace polycut::geometry {

/// Result of fitting x ~ A X + t.
struct AffineFit {
    Mat3 A = Mat3::Identity(); ///< linear part (the deformation gradient for a tet)
    Vec3 t = Vec3::Zero();     ///< translation [m]
    Vec3 rest_centroid = Vec3::Zero();
    Vec3 world_centroid = Vec3::Zero();
    bool ok = true; ///< false when the rest points span less than 3D
};

/// Fits x_i ~ A X_i + t in the least-squares sense (weights uniform).
AffineFit fit_affine(std::span<const Vec3> rest, std::span<const Vec3> world);

/// Rotation of the polar decomposition A = R S with det R = +1 (reflections are resolved by
/// flipping the axis of the smallest singular value, as for inverted elements).
Mat3 polar_rotation(const Mat3& A);

} // namespace polycut::geometry
