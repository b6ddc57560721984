// World-to-rest mapping of sweep triangles (issue 5 item 1, DESIGN.md sec. 3): a uniform grid
// over the deformed cell bounds, refitted each tick, finds the cell under a world point; the
// point goes to rest space through the inverse of that cell's least-squares affine fit.
#pragma once

#include "polycut/cut/cut_options.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/mesh.hpp"

#include <optional>
#include <span>
#include <vector>

namespace polycut::cut {

/// Maps world points and sweep triangles to rest space through per-cell affine fits.
class WorldToRest {
public:
    /// Binds to `mesh` (must outlive this object). Call refit() before mapping.
    explicit WorldToRest(const mesh::Mesh& mesh);

    /// Refits every cell's affine map and the grid to the current world positions (#N) [m].
    /// Call once per tick, and after each cut (the topology changed). O(mesh). With
    /// `with_fits` false only the deformed bounds and the grid are refitted (for candidates());
    /// map_point(), locate() and map_triangle() then need a full refit first.
    void refit(std::span<const Vec3> world, bool with_fits = true);
    /// For candidates() only, around a blade: indexes just the cells whose deformed bounds
    /// overlap `region` [m] (one pass over the cells' nodes, no grid over all of them; issue 12
    /// item 5). candidates() of a box inside `region` then returns exactly what it returns
    /// after refit(). Returns false, and refits the whole grid instead, when more than
    /// `max_cells` cells overlap (a long cut request: a linear filter per query would cost more).
    bool refit_near(
        std::span<const Vec3> world, const geometry::Aabb& region, std::size_t max_cells = 4096);
    /// refit_near() reads the cells' nodes from its own flat copy of the node lists (the
    /// mesh's per-cell vectors cost a cache miss per cell). After an edit of the mesh the owner
    /// names the cells whose node lists changed (appended cells are found by count), or says
    /// that cells or nodes were renumbered (the copy is then made again from the mesh). Checked
    /// against the mesh under POLYCUT_CHECK_UNDO=1.
    void cells_changed(std::span<const Index> changed, bool renumbered);
    /// Makes refit_near()'s flat copy of the node lists now (O(mesh)), so that the first cut
    /// of a scene, or the first after a renumbering, does not (CutPipeline::prepare()).
    void prepare();
    /// Same with displacements u (#N x 3) [m]: world = rest + u.
    void refit_displaced(const MatX3& u);

    /// Rest position of world point x [m]: through the fit of the cell containing x (the one
    /// whose rest preimage lies deepest inside it), else of the nearest cell (extrapolated).
    Vec3 map_point(const Vec3& x) const;
    /// Cell used for x (kNone if the mesh is empty).
    Index locate(const Vec3& x) const;

    /// Maps a world triangle to rest space. With max_edge > 0 [m] the triangle is first divided
    /// into n^2 similar triangles whose edges are at most max_edge, each corner mapped through
    /// its own cell, so the rest cut follows a deformation that varies across the triangle.
    std::vector<Triangle> map_triangle(const Triangle& world, double max_edge = 0) const;

    /// Rest corners of the world triangle `w` from one affine map of the triangle's own
    /// parameters (u, v), fitted by least squares to the rest images of the points of a
    /// barycentric lattice (edges at most `max_edge` [m], at least 2 per side) that lie inside
    /// the tissue, each mapped through the cell containing it (the inverse of that cell's affine
    /// fit; exact for a tet). Works after refit_near() or refit() (candidates() only) with the
    /// world positions `world` of the nodes. Where the deformation varies across the cells a
    /// triangle meets (a block pressed flat above a fixed base), this follows the tissue under
    /// the triangle and not an average over every node of those cells, and the corners outside
    /// the tissue follow the triangle's own plane. Empty when fewer than three lattice points
    /// inside the tissue span the triangle's plane.
    std::optional<Triangle> fit_triangle(
        const Triangle& w, std::span<const Vec3> world, double max_edge) const;

    /// Cells whose deformed bounds overlap `box`.
    std::vector<Index> candidates(const geometry::Aabb& box) const;

private:
    const mesh::Mesh& m_mesh;
    std::vector<Vec3> m_world;
    std::vector<geometry::AffineFit> m_fit;
    std::vector<Mat3> m_inverse;
    std::vector<geometry::Aabb> m_box;
    geometry::Aabb m_all;
    Eigen::Vector3i m_dims { 1, 1, 1 };
    Vec3 m_step = Vec3::Ones();
    std::vector<Index> m_bucket_start; ///< (#buckets + 1) offsets into m_bucket_cells
    std::vector<Index> m_bucket_cells; ///< cells per bucket, bucket after bucket
    std::vector<Index> m_fill; ///< work array of refit()
    bool m_near_only = false; ///< refit_near(): only m_near is valid
    std::vector<std::pair<Index, geometry::Aabb>> m_near; ///< cells (ascending) near the region
    /// Flat copy of the cells' node lists for refit_near(): cell c's nodes are
    /// m_pool[m_slot[c] .. m_slot[c] + m_count[c]), its slot holding up to m_room[c].
    bool m_flat_ok = false;
    std::vector<std::size_t> m_slot;
    std::vector<int> m_count, m_room;
    std::vector<Index> m_pool;

    void copy_cell(std::size_t c);
    void refresh_flat();

    Eigen::Vector3i bucket(const Vec3& x) const;
    double depth_outside(Index c, const Vec3& X) const;
};

} // namespace polycut::cut
