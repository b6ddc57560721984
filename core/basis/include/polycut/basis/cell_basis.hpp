// Per-cell basis dispatch (DESIGN.md sec. 1): tets get P1, hexes Q1, general polyhedra a
// polyhedral basis (mean value, 000; harmonic, 001) chosen by BasisOptions.
#pragma once

#include "polycut/basis/cell_integration.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/options/basis.hpp"

namespace polycut::basis {

/// Integration data of cell `cell` of `mesh` in rest space: P1 for tets (exact, 1 point), Q1 for
/// hexes (2x2x2 Gauss), the polyhedral basis of `options` otherwise. Throws MeshError naming the
/// cell for an inverted or degenerate cell; std::logic_error for a basis that is not built in.
CellIntegration integrate_cell(const mesh::Mesh& mesh, Index cell, const BasisOptions& options);

} // namespace polycut::basis
