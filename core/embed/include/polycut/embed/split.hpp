// Splitting an embedded surface along a cut (issue 15 item 2; 001 sec. 7, 003 sec. 8): "the cut
// lips are as detailed as the skin". In rest space, the skin triangles near the mesh's new Cut
// faces are corefined with those faces (CGAL, exact constructions), so no skin triangle crosses
// the cut; a skin vertex on the cut gets one copy per side, each embedded in a cell on its own
// side; and the Cut faces, clipped to the inside of the detailed surface, close the opening as
// lip triangles whose border is the skin's own cut curve. Only the triangles near the new cut
// faces are touched (and the vertices whose cells the cut changed are embedded again).
#pragma once

#include "polycut/embed/embedding.hpp"

#include <functional>
#include <map>
#include <vector>

namespace polycut::embed {

/// What the splitting keeps between cuts.
struct SplitState {
    /// The lip vertex at each mesh node (lip corners that are nodes of a Cut face).
    std::map<Index, std::uint32_t> node_vertex;
    /// Vertices that share a rest position with another (the copies of a vertex on a cut),
    /// by rest position.
    std::map<std::array<double, 3>, std::vector<std::uint32_t>> copies;
};

/// What one split did.
struct SplitReport {
    std::size_t cut_faces = 0; ///< Cut faces of the mesh taken (both sides)
    std::size_t cut_triangles = 0; ///< triangles of the cut surface (one side) corefined
    std::size_t patch_triangles = 0; ///< skin triangles corefined (near the cut)
    std::size_t skin_triangles_added = 0; ///< net change of the skin's triangle count
    std::size_t vertices_added = 0; ///< copies on the cut, lip vertices
    std::size_t lip_triangles_added = 0; ///< both sides
    std::size_t lips_remade = 0; ///< earlier lip triangles on the cut faces, made again
    std::size_t reembedded = 0; ///< vertices embedded again
    /// The cut runs over skin an earlier cut split (a Cut face grew): nothing was done, the
    /// caller embeds the surface anew and splits it along all the mesh's Cut faces at once.
    bool overlaps_earlier_cut = false;
    double corefine_ms = 0; ///< CGAL corefinement [ms]
    double total_ms = 0; ///< the whole call [ms]
};

/// What the cut did to the mesh, as far as the splitting needs it.
struct CutChange {
    std::vector<Index> cut_faces; ///< Cut faces made by the cut (ids into mesh.faces, both sides)
    /// (node, its copy) for the nodes the cut separated: a lip corner at such a node (the front
    /// of an earlier cut that this one carried on through) takes the copy on its own side.
    std::vector<std::pair<Index, Index>> duplicated;
    std::vector<std::uint32_t> reembed; ///< vertices to embed again (their cells changed)
};

/// Splits `e` along `change.cut_faces` of `mesh` (the lips of a region an earlier cut closed are
/// made again when a Cut face there grew) and embeds the vertices it made or regrouped, and
/// `change.reembed`, in `mesh`. `inside(X)` says whether a rest point lies inside the detailed
/// surface as it was loaded (the lips are the part of the cut inside it). Throws polycut::Error
/// when CGAL cannot corefine (the caller then embeds the surface anew, unsplit). Does nothing
/// and says `overlaps_earlier_cut` when an earlier cut's seam lies on the new Cut faces.
SplitReport split_along_cut(Embedding& e, SplitState& state, const mesh::Mesh& mesh,
    const CutChange& change, const std::function<bool(const Vec3&)>& inside, basis::PolyBasis poly);

} // namespace polycut::embed
