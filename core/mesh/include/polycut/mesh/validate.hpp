// Mesh validation: the invariants of mesh.hpp checked cell by cell and face by face, and the
// closed-surface check the cutter runs after every cut (issue 5, item 6). Everything is linear in
// the mesh size (hashing, no all-pairs loops), so it can run after each cut in tests and debug
// builds.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <string>
#include <vector>

namespace polycut::mesh {

/// Tolerances and switches of check_mesh(). All tolerances are relative (dimensionless).
struct ValidationOptions {
    /// A face is non-planar when its planarity_error exceeds planarity_tol * (bounding-box
    /// diagonal of its owner cell).
    double planarity_tol = 1e-9;
    /// Two nodes coincide when closer than duplicate_tol * (bounding-box diagonal of the mesh).
    double duplicate_tol = 1e-12;
    /// Cells with a rest volume at or below min_volume [m^3] are reported as zero-volume, in
    /// addition to cells with |volume| <= 1e-12 * (cell diagonal)^3.
    double min_volume = 0;
    /// Report cells that are not convex (needed by the `mvc` method).
    bool require_convex = false;
    /// Look for coincident nodes. Pairs whose nodes both lie on Cut faces are allowed: a cut
    /// separates material by duplicating the nodes of the cut surface.
    bool check_duplicates = true;
    /// Accept nodes that no cell uses (they carry no mass and make the stiffness singular).
    bool allow_unused_nodes = false;
    /// Check that the boundary (skin + cut faces) is a closed, oriented 2-manifold.
    bool check_boundary = true;
};

/// One defect found by check_mesh().
struct ValidationIssue {
    enum class Kind {
        NonFinite, ///< a rest position is NaN or infinite (node)
        BadAdjacency, ///< face table inconsistent: ids out of range, owner/neighbour not
                      ///< listing the face, wrong Interior/boundary tag, repeated nodes
        BadShape, ///< Tet/Hex shape tag does not match the cell's nodes and faces
        OpenCell, ///< an edge of the cell's outward loops is not used exactly twice
                  ///< in opposite directions
        NonPlanarFace, ///< face farther from its plane than planarity_tol * cell size
        InvertedCell, ///< negative rest volume
        ZeroVolumeCell, ///< rest volume (nearly) zero or below min_volume
        NonConvexCell, ///< only with require_convex
        DuplicateNodes, ///< two nodes at the same rest position (node, other node in text)
        UnusedNode, ///< a node no cell uses
        NonManifoldBoundary, ///< a boundary edge not shared by exactly two boundary faces with
                             ///< opposite directions
    };
    Kind kind = Kind::BadAdjacency;
    Index cell = kNone; ///< offending cell, kNone if none applies
    Index face = kNone; ///< offending global face id, kNone if none applies
    Index node = kNone; ///< offending node, kNone if none applies
    Index other = kNone; ///< DuplicateNodes: the node `node` coincides with; kNone otherwise
    std::string message; ///< what is wrong, with numbers
};

/// Short name of an issue kind ("inverted cell", ...).
const char* kind_name(ValidationIssue::Kind kind);

/// All defects of a mesh, in a deterministic order: non-finite nodes, face-table adjacency,
/// per-cell checks in cell order (shape, closedness, planarity, volume, convexity), then
/// duplicate and unused nodes, then the boundary surface. Geometric checks of a cell are skipped
/// when its topology is already broken.
std::vector<ValidationIssue> check_mesh(const Mesh& mesh, const ValidationOptions& options = {});

/// Throws MeshError naming the cell and face of the first issue check_mesh() finds; its message
/// also says how many issues there are in total.
void validate(const Mesh& mesh, const ValidationOptions& options = {});

/// Result of check_boundary_surface().
struct SurfaceCheck {
    bool closed = true; ///< no open and no non-manifold edges
    bool oriented = true; ///< every edge shared by two faces is used in opposite directions
    Index components = 0; ///< connected components of the boundary faces (through edges)
    Index boundary_edges = 0; ///< edges used by a single boundary face (holes)
    Index nonmanifold_edges = 0; ///< edges used by three or more boundary faces
    Index misoriented_edges = 0; ///< edges used twice in the same direction
    Index faces = 0; ///< number of boundary faces
    Index first_bad_face = kNone; ///< a boundary face on the first bad edge, kNone if none
    /// closed && oriented: a closed, consistently oriented 2-manifold per component (up to
    /// non-manifold vertices, which an edge check cannot see).
    bool ok() const { return closed && oriented; }
};

/// Checks that the boundary faces (skin + cut) form a closed, consistently oriented 2-manifold per
/// connected component. Edges are matched by their end nodes, so a node hanging on another face's
/// edge shows up as boundary edges. O(boundary face corners) with hashing.
SurfaceCheck check_boundary_surface(const Mesh& mesh);

} // namespace polycut::mesh
