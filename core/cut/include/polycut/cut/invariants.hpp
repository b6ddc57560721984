// Invariants that must hold after every cut (issue 5 item 6, DESIGN.md sec. 3): rest volume
// conserved, cells of positive volume and convex, boundary surface closed and oriented, no
// non-finite number, face table consistent; components counted.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <string>

namespace polycut::cut {

/// Tolerances of check_cut_invariants (relative, dimensionless).
struct InvariantOptions {
    double volume_tol = 1e-9; ///< |V - V_before| <= volume_tol * V_before
    /// A cell is convex when no node lies farther than convex_tol * (cell bounding-box diagonal)
    /// outside any of its face planes (snapping leaves interface faces up to CutOptions::snap
    /// times the cell thickness off their plane).
    double convex_tol = 2e-2;
    bool require_convex = true;
    /// Planarity tolerance passed to mesh::check_mesh, relative to the cell diagonal.
    double planarity_tol = 2e-2;
};

/// What check_cut_invariants measured.
struct CutInvariants {
    double volume_before = 0, volume = 0; ///< total rest volume [m^3]
    double volume_error = 0; ///< |V - V_before| / V_before
    Index cells = 0, nodes = 0;
    Index nonpositive_cells = 0; ///< cells of rest volume <= 0
    double min_volume_ratio = 0; ///< smallest cell volume / largest cell volume
    Index nonconvex_cells = 0; ///< cells violating convex_tol
    double max_convexity_violation = 0; ///< largest violation / cell diagonal
    bool finite = true; ///< every rest coordinate finite
    Index mesh_issues = 0; ///< defects mesh::check_mesh found (adjacency, shape...)
    bool surface_closed = false; ///< boundary closed and oriented (check_boundary_surface)
    Index surface_components = 0; ///< connected components of the boundary surface
    Index components = 0; ///< connected components of cells (shared nodes)
    std::string first_problem; ///< description of the first failure, empty if ok
    bool ok() const { return first_problem.empty(); }
};

/// Convexity violation of cell c: the largest distance of a node of c outside one of its face
/// planes (each face's Newell normal through its centroid), over the cell's bounding-box
/// diagonal; 0 for a convex cell.
double convexity_violation(const mesh::Mesh& mesh, Index c);

/// Why cell c's surface is not closed and consistently oriented ("" when it is): every directed
/// edge of its outward face loops must appear once, and its reverse once. O(faces of c).
std::string open_cell_problem(const mesh::Mesh& mesh, Index c);

/// Checks every invariant; O(mesh). `volume_before` is the total rest volume before the cuts.
CutInvariants check_cut_invariants(
    const mesh::Mesh& mesh, double volume_before, const InvariantOptions& options = {});

} // namespace polycut::cut
