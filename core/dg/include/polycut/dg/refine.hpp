// Stress-based adaptivity of DG meshes (003 sec. 10, issue 13 item 5): cells whose largest
// absolute principal stress exceeds a threshold are split 1-to-8 (hexes, at their edge, face
// and body midpoints), and the children start from the parent's polynomial. DG needs no
// conformity, but the mesh's face table does: a face of an unsplit neighbour that a split cell
// shares is split into the same four quads (the neighbour becomes a polyhedron with coplanar
// faces), and every face through a split edge gets the edge's midpoint, so faces still match
// node for node and the boundary stays closed.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"

#include <vector>

namespace polycut::dg {

class DgModel;

/// Largest absolute principal stress [Pa] of each cell at its centroid, from the field x
/// (linear strain of R^T F with R the cell's cached rotation; identity before a corotated
/// assembly). With `directions`, also each cell's principal direction of that stress (unit).
std::vector<double> principal_stress(
    const DgModel& model, const MatX3& x, std::vector<Vec3>* directions = nullptr);

/// A refined mesh and, per new cell, the old cell whose polynomial it starts from.
struct Refinement {
    mesh::Mesh mesh;
    std::vector<Index> source;
    std::vector<std::uint8_t> child; ///< per new cell: 1 for a child of a split cell
    Index split = 0; ///< cells split 1-to-8
};

/// Splits the listed cells that are hexes 1-to-8 (others are skipped). Node ids of the old mesh
/// are kept; new nodes are appended.
Refinement refine_hexes(const mesh::Mesh& m, const std::vector<Index>& cells);

/// Coefficient rows (#coeffs_new x 3) on `new_model` of a field given by rows `field` on
/// `old_model`: each new cell takes the polynomial of source[c], fitted exactly (least squares
/// through the cell's nodes, the midpoints of node pairs and its centroid, unisolvent for
/// p <= 2); cells listed as unchanged copy their rows.
MatX3 transfer_field(const DgModel& old_model, const MatX3& field, const DgModel& new_model,
    const std::vector<Index>& source, const std::vector<std::uint8_t>& unchanged = {});

} // namespace polycut::dg
