// The cell-splitting cutter of the `mvc` and `harmonic` methods (seed 000 sec. 5): splits convex
// cells along planes with edge nodes shared by every cell around an edge, splits the faces that
// lie in a sweep polygon's plane along the polygon's edges, tags the covered part Cut on both
// sides and duplicates the nodes the cut separates, with pocket nodes where nothing can open.
//
// Mutation contract: a call only appends nodes and faces, rewrites the face loops and node lists
// of the cells it reports as changed, and appends cells (sliver merging may remove cells; then
// CutReport::cell_map renumbers). Node and face ids stay valid. Invalid input throws InputError
// before anything changes.
#pragma once

#include "polycut/cut/cut_options.hpp"
#include "polycut/cut/cut_report.hpp"
#include "polycut/mesh/mesh.hpp"

#include <memory>
#include <span>

namespace polycut::cut {

/// Stateful cutter working on a mesh it does not own. It keeps node-to-cell adjacency and cell
/// bounds between calls; call rebuild() if the mesh is edited by anything else.
class Cutter {
public:
    /// Binds to `mesh` (which must outlive the cutter) and builds the adjacency, O(mesh).
    explicit Cutter(mesh::Mesh& mesh, CutOptions options = {});
    ~Cutter();
    Cutter(const Cutter&) = delete;
    Cutter& operator=(const Cutter&) = delete;

    /// Cuts along sweep triangles given in REST space [m], one after the other (progressive: each
    /// extends the cut of the previous ones). Throws InputError (mesh unchanged) if any triangle
    /// has a non-finite coordinate, is degenerate, or lies absurdly far away. With
    /// `max_changed_cells` > 0 the call stops after the first triangle that brings the cells it
    /// changed, or their CutReport::work, to that many (CutReport::triangles says how many were
    /// cut; the caller passes the rest again later); with `may_stop` given (one flag per
    /// triangle), only after a triangle whose flag is set (the halves of a coarsened strip quad
    /// are cut together).
    CutReport cut(std::span<const Triangle> rest_triangles, Index max_changed_cells = 0,
        std::span<const char> may_stop = {});

    /// Splits cells crossed by the plane through `point` with normal `normal` [rest space] into
    /// two convex cells each, without separating anything. `cells` lists the cells to split (all
    /// cells the plane crosses if empty). Throws InputError on a non-finite or zero normal.
    CutReport split_by_plane(
        const Vec3& point, const Vec3& normal, std::span<const Index> cells = {});

    /// Recomputes the adjacency after external edits of the mesh.
    void rebuild();

    const CutOptions& options() const;
    const mesh::Mesh& mesh() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// One-off convenience: cuts `mesh` along rest-space sweep triangles (builds a Cutter, O(mesh)).
CutReport cut_rest(
    mesh::Mesh& mesh, std::span<const Triangle> rest_triangles, const CutOptions& options = {});

} // namespace polycut::cut
