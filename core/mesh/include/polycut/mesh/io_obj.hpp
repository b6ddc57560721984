// Wavefront OBJ output for triangle surfaces.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <string>
#include <vector>

namespace polycut::mesh {

/// Triangles as rows of 3 vertex indices (#T x 3), 0-based.
using MatX3i = Eigen::Matrix<Index, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Writes positions (#V x 3) [m] and triangles (#T x 3, 0-based) as an OBJ file ("v" and "f"
/// lines, 1-based in the file). Throws InputError for an index out of range and FileError when
/// the file cannot be written.
void write_obj(const std::string& path, const MatX3& positions, const MatX3i& triangles);

/// As above with positions (#V) [m] and triangles (#T) as vectors.
void write_obj(const std::string& path, const std::vector<Vec3>& positions,
    const std::vector<std::array<Index, 3>>& triangles);

} // namespace polycut::mesh
