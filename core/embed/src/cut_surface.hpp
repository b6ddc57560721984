// Private to split.cpp: the rest-space cut surface an embedded surface is split along, built
// from the mesh's Cut faces (decision 0033). One side's faces only (both lips of a cut cover
// the same rest surface), and made conforming: the faces' corners are welded where they agree
// up to rounding, and a corner that lies on another face's edge (a T-junction: the blade
// stopped inside a cell and a later cut carried on through it, or a merged cell's face spans
// two smaller ones) is inserted into that edge, so the triangles share every edge they touch.
#pragma once

#include "corefine.hpp"
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <map>
#include <set>
#include <vector>

namespace polycut::embed::detail {

using Key = std::array<double, 3>;
inline Key key_of(const Vec3& p) {
    return { p.x(), p.y(), p.z() };
}

struct Box {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -Vec3::Constant(std::numeric_limits<double>::infinity());
    void add(const Vec3& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    bool overlaps(const Box& b, double pad) const {
        return (lo.array() <= b.hi.array() + pad).all() && (b.lo.array() <= hi.array() + pad).all();
    }
};

struct CutSurface {
    std::vector<Index> faces; ///< the usable Cut faces (boundary, tag Cut, >= 3 nodes), both sides
    std::size_t extension_quads = 0; ///< quads carrying the cut past the mesh's skin
    std::size_t slit_faces = 0; ///< Cut faces left out: both faces of a slit inside one cell
    std::vector<Vec3> normal; ///< each face's rest normal (outward for its cell)
    std::vector<int> side; ///< 0: the side taken, 1: the other
    TriangleSet cut; ///< side 0's faces, welded, T-junctions inserted, triangulated
    std::vector<std::size_t> triangle_face; ///< index into `faces` of each triangle
    std::vector<Box> triangle_box;
    Box all;
    /// Each side's nodes by the welded rest position of the node (the cut point there).
    std::map<Key, Index> side_node[2];
    /// The crack front: welded points of nodes both sides share, and their extensions past the
    /// mesh's skin (the material has not parted there).
    std::set<Key> front;
    double tolerance = 0; ///< [m] welding distance: rounding, far below any feature
    double edge_length = 0; ///< [m] the faces' mean edge length (a grid size)
    /// Side 0's faces as loops of welded corners (index into `faces`, cut points).
    std::vector<std::pair<std::size_t, std::vector<std::uint32_t>>> loops;
};

/// Builds the cut surface of `cut_faces` (ids into mesh.faces; others are skipped).
CutSurface build_cut_surface(const mesh::Mesh& mesh, const std::vector<Index>& cut_faces);

/// Fits the cut surface to the skin's vertices `points` (rest positions of the patch): a cut
/// corner within the tolerance of a skin vertex moves onto it, and a skin vertex within the
/// tolerance of a cut edge is inserted into that edge (an earlier cut's end on the skin lies on
/// the crack front, where the next faces begin). Otherwise the exact corefinement makes slivers
/// between the two that the lips cannot close. Keeps side_node's keys in step.
void fit_to_skin(CutSurface& s, const std::vector<Vec3>& points);

/// Whether p lies on triangle (a, b, c) (within `tol` of its plane, inside its edges).
bool on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double tol);

/// Whether the cut surface meets an earlier cut (the caller then splits anew along all the Cut
/// faces, decision 0033): one of its faces shares a node with a Cut face of the mesh not in
/// `fresh_faces`, or a vertex on an earlier seam (`seam_vertices`, by rest position) lies on
/// one of its triangles.
bool meets_earlier_cut(const CutSurface& s, const mesh::Mesh& mesh,
    const std::vector<Index>& fresh_faces,
    const std::map<Key, std::vector<std::uint32_t>>& seam_vertices);

} // namespace polycut::embed::detail
