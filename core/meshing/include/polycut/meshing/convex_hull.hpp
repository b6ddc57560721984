// One convex polyhedral cell from a point set: the convex hull (CGAL convex_hull_3, exact
// predicates) with its coplanar triangles merged into planar polygon faces, as
// mesh::Mesh::from_polyhedra takes them. Seed 000 Fig. 1 is such a cell (24 nodes).
#pragma once

#include "polycut/common/error.hpp"
#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::meshing {

/// A convex polyhedron whose nodes are all corners.
struct ConvexPolyhedron {
    std::vector<Vec3> nodes; ///< corner positions (#N) [m], in the order of the input points
    /// Face loops (#F, each >= 3 node ids), counter-clockwise seen from outside (right-hand
    /// normal points out); no three consecutive nodes of a loop are collinear.
    std::vector<std::vector<Index>> faces;
};

/// Why a point set does not make a convex cell. where() is "points/<i>" when point i is at
/// fault (index() == i), "points" when the set as a whole is (index() == kNone).
class ConvexHullError : public InputError {
public:
    ConvexHullError(Index index, const std::string& what);
    /// The offending point, or kNone.
    Index index() const noexcept { return m_index; }

private:
    Index m_index;
};

/// The convex hull of `points` [m] as one polyhedron: its nodes are the points themselves (same
/// order), its faces the hull's planar facets (triangles in one plane merged, tested with exact
/// predicates on the double coordinates). Throws ConvexHullError for fewer than 4 points, a
/// non-finite coordinate, a repeated point, a set with no volume (all points on one plane), or a
/// point that is not a corner of the hull (inside it, or on a face or an edge): every node of a
/// polyhedral cell must be a corner, since the mean value and harmonic bases are built on the
/// faces' corners.
ConvexPolyhedron convex_hull(const std::vector<Vec3>& points);

/// One cell (CellShape::Polyhedron, or Tet for 4 points) made of convex_hull(points).
mesh::Mesh convex_hull_cell(const std::vector<Vec3>& points);

/// The 24 corners of a truncated octahedron of edge length `edge` [m] centred at `center` [m]:
/// all permutations of (0, +-1, +-2) times edge / sqrt(2). It has 8 regular hexagons and 6
/// squares (axis-aligned, at +-sqrt(2) edge from the centre), volume 8 sqrt(2) edge^3,
/// circumradius sqrt(5/2) edge. Throws InputError unless edge is finite and > 0.
std::vector<Vec3> truncated_octahedron_points(double edge, const Vec3& center = Vec3::Zero());

} // namespace polycut::meshing
