// 3D mean value coordinates as finite element shape functions on convex polyhedra (seed 000 sec.
// 3.2-3.5): values and analytic gradients, and the cell's integration by the heuristic of 000
// eq. 14-16 or by a reference Gauss rule on the centroid tetrahedralization.
#pragma once

#include "polycut/basis/cell_geometry.hpp"
#include "polycut/basis/cell_integration.hpp"
#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::basis {

/// How a mean value cell is integrated.
enum class MvcRule {
    Heuristic, ///< 000 eq. 14-16: one sample per node and per surface triangle
    Reference, ///< Gauss rule of selectable degree on the centroid tetrahedralization
};

/// Mean value coordinates of one convex polyhedron with planar faces. Faces are triangulated by
/// mean_value_triangulation(); the weights are those of Ju, Schaefer & Warren 2005 (equal to 000
/// eq. 7-8), normalized as 000 eq. 9. Immutable after construction; evaluate() is thread-safe.
class MeanValueCell {
public:
    /// Builds the cell from node positions (#n) [m] and outward face loops of local indices.
    /// Throws MeshError for fewer than 4 nodes, a face with fewer than 3 nodes, or a
    /// non-positive volume.
    MeanValueCell(std::vector<Vec3> nodes, const std::vector<std::vector<Index>>& loops);
    explicit MeanValueCell(const CellGeometry& cell);

    /// Number of nodes (= number of shape functions).
    Index num_nodes() const { return Index(m_nodes.size()); }
    /// Node positions (#n) [m].
    const std::vector<Vec3>& nodes() const { return m_nodes; }
    /// The surface triangulation the coordinates are defined on.
    const std::vector<SurfaceTriangle>& triangles() const { return m_triangles; }
    /// Cell volume [m^3].
    double volume() const { return m_volume; }
    /// Volume centroid [m].
    const Vec3& centroid() const { return m_centroid; }
    /// Bounding-box diagonal [m].
    double size() const { return m_size; }

    /// Shape function values phi (#n) at x [m] and, if grad is given, their gradients (#n x 3)
    /// [1/m]. x must lie in the closed cell. Never divides by zero: within 1e-12 size of the
    /// surface the values are the barycentric coordinates of the nearest surface triangle (the
    /// limit on the boundary; the Kronecker delta at a node); within 1e-7 size the gradient is
    /// taken at a point moved towards the centroid by a relative 1e-6 (or more).
    void evaluate(const Vec3& x, VecX& phi, MatX3* grad = nullptr) const;

    /// Quadrature of the cell with `rule` (gauss_degree is used by MvcRule::Reference; a
    /// 4-node cell always gets its exact 1-point rule). Lumped volumes are mu_i V (000 eq. 14,
    /// 18) for both rules.
    CellIntegration integrate(MvcRule rule, int gauss_degree = 2) const;

    /// Volume fractions mu_i of 000 eq. 14 (#n); they sum to 1.
    VecX volume_fractions() const;

private:
    void evaluate_interior(const Vec3& x, VecX& phi, MatX3* grad) const;
    bool evaluate_on_surface(const Vec3& x, VecX& phi, double rel_tol) const;

    std::vector<Vec3> m_nodes;
    std::vector<SurfaceTriangle> m_triangles;
    std::vector<Vec3> m_tri_normal; ///< unit outward normal per triangle
    std::vector<double> m_tri_area; ///< [m^2]
    /// The surface triangles' edges, each once (a < b), and per triangle edge e (from node e to
    /// node e + 1) its index here, negated minus one when it runs from b to a: the edge terms of
    /// the coordinates and their gradients are computed once per edge, not per triangle side.
    std::vector<std::array<Index, 2>> m_edges;
    std::vector<std::array<Index, 3>> m_tri_edges;
    double m_volume = 0;
    Vec3 m_centroid = Vec3::Zero();
    double m_size = 0;
};

/// Triangulation of the face loops (outward, local indices into nodes [m]) that mean value cells
/// use: per face the Delaunay triangulation (largest smallest angle), which avoids the needle
/// triangles of a fan on many-sided faces. It depends on the face's vertex positions only, not on
/// the loop's orientation or first vertex, so two cells sharing a face triangulate it identically
/// (exact C0). Degenerate triangles are avoided where the face allows; triangles of area below
/// area_tol [m^2] (collinear vertices) are dropped. Triangles are oriented as the loops.
std::vector<SurfaceTriangle> mean_value_triangulation(
    const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops, double area_tol);

/// Values phi (#n) and optionally gradients (#n x 3) [1/m] of the mean value coordinates of the
/// cell (nodes, outward loops) at x [m]. Builds a MeanValueCell; use the class for many points.
void mean_value(const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops,
    const Vec3& x, VecX& phi, MatX3* grad = nullptr);

/// Integration of a mean value cell (nodes, outward loops) by `rule`.
CellIntegration integrate_mean_value(const std::vector<Vec3>& nodes,
    const std::vector<std::vector<Index>>& loops, MvcRule rule, int gauss_degree = 2);

/// Integration of cell `cell` of `mesh` as a mean value cell; node order is Cell::nodes.
CellIntegration integrate_mean_value(
    const mesh::Mesh& mesh, Index cell, MvcRule rule, int gauss_degree = 2);

} // namespace polycut::basis
