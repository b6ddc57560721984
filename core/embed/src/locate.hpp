// Point location in a mesh at rest: a uniform grid of cell bounding boxes.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::embed::detail {

class CellGrid {
public:
    explicit CellGrid(const mesh::Mesh& mesh);
    /// Cells whose bounding box contains p (padded by a relative 1e-9).
    void candidates(const Vec3& p, std::vector<Index>& out) const;
    /// The cell whose bounding box is nearest p, and that distance [m].
    Index nearest(const Vec3& p, double& distance) const;
    /// Whether the convex cell contains p (within a relative 1e-9 of its size).
    bool contains(Index cell, const Vec3& p) const;

private:
    const mesh::Mesh* m_mesh;
    Vec3 m_lo, m_step;
    Eigen::Vector3i m_dims;
    std::vector<std::vector<Index>> m_bins;
    std::vector<Vec3> m_cell_lo, m_cell_hi;
    Eigen::Vector3i bin_of(const Vec3& p) const;
};

} // namespace polycut::embed::detail
