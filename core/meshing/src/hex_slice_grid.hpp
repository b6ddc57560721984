// Private to the meshing module: the CGAL half of hex_slice() (hex_slice_grid.cpp). A closed
// surface refined along the planes of a grid in exact arithmetic, so that every triangle lies in
// one grid cube, and the side of the surface each grid corner lies on.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/meshing/surface.hpp"

#include <array>
#include <stdexcept>
#include <vector>

namespace polycut::meshing::detail {

/// Plane coordinates of a grid of cubes: planes[a][i], i = 0..n[a], along axis a [m].
struct SliceGrid {
    std::array<std::vector<double>, 3> planes;
    int cubes(int axis) const { return int(planes[std::size_t(axis)].size()) - 1; }
};

/// The surface refined along the grid planes.
struct SlicedSurface {
    std::vector<Vec3> points; ///< vertices [m], rounded from the exact ones
    /// per vertex and axis: the grid plane it lies on exactly, or -1
    std::vector<std::array<int, 3>> plane;
    /// per vertex and axis: the slab (planes[i] < x < planes[i + 1]) when not on a plane
    std::vector<std::array<int, 3>> slab;
    std::vector<std::array<Index, 3>> triangles; ///< outward
    std::vector<std::array<int, 3>> cube; ///< per triangle: the cube (i, j, k) it lies in
};

/// The grid is in a degenerate position for this surface (a vertex on a grid plane, a
/// triangle in one, a corner on the surface): move it and try again.
struct DegenerateGrid : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Refines the closed, outward `surface` along every inner grid plane (CGAL corefinement with
/// exact constructions). Throws DegenerateGrid.
SlicedSurface slice_surface(const SurfaceMesh& surface, const SliceGrid& grid);

/// +1 inside the closed surface, -1 outside, for each point (CGAL Side_of_triangle_mesh, exact
/// predicates). Throws DegenerateGrid if a point lies on the surface.
std::vector<int> sides(const SurfaceMesh& surface, const std::vector<Vec3>& points);

} // namespace polycut::meshing::detail
