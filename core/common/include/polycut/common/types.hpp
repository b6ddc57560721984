// Scalar and vector types shared by every core module. SI units throughout: positions [m],
// forces [N], times [s], pressures and moduli [Pa], densities [kg/m^3].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace polycut {

using Index = std::int32_t;          ///< node, face and cell indices; -1 means "none"
inline constexpr Index kNone = -1;

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
/// Per-node rows of 3 (#N x 3), row-major so that a flat view is [x0 y0 z0 x1 ...].
using MatX3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Flat DOF view of an (#N x 3) row-major matrix as a (3#N) vector.
inline Eigen::Map<VecX> flat(MatX3& m) { return {m.data(), m.size()}; }
inline Eigen::Map<const VecX> flat(const MatX3& m) { return {m.data(), m.size()}; }

} // namespace polycut
