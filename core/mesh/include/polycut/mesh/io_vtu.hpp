// VTK XML unstructured grid (.vtu) output for ParaView and meshio.
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <string>
#include <vector>

namespace polycut::mesh {

/// A named field over points (#N x k) or cells (#C x k); k = 1 scalar, 3 vector, 9 tensor.
struct Field {
    std::string name; ///< array name in the file ("displacement", "von_mises")
    MatX values; ///< one row per point or cell, SI units
};

/// Which VTK cell types the writer uses.
///
/// When cells are written as VTK_POLYHEDRON (42), the file lists them sorted by node count
/// (stable) and adds the cell array "polycut_cell" (Int64) with each file cell's index in the
/// Mesh; cell fields follow the same order. That is the layout meshio 5.0 reads correctly: it
/// rejects polyhedra mixed with other cell types, and it misassigns cell data when polyhedra
/// with fewer nodes follow ones with more (meshio PR #1463). ParaView reads every layout.
enum class VtuCellTypes {
    /// VTK_TETRA (10) / VTK_HEXAHEDRON (12) for Tet/Hex cells, in mesh order, when the mesh has
    /// no polyhedral cell; when it has one, every cell as VTK_POLYHEDRON (meshio-readable).
    Auto,
    /// Tet/Hex cells as 10/12, other cells as 42, in mesh order (ParaView only when mixed).
    Native,
    /// Every cell as VTK_POLYHEDRON (42) with `faces` and `faceoffsets`.
    AllPolyhedra,
};

/// Writes the mesh as an ASCII .vtu file. `positions` are the world positions (#N) [m]; the rest
/// positions when null. Field rows must match the node or cell count. The file is written to a
/// temporary name and renamed, so readers never see half a file. Throws FileError when the file
/// cannot be written and InputError for fields of the wrong size or a bad name (empty, XML
/// special characters, or "polycut_cell").
void write_vtu(const std::string& path, const Mesh& mesh,
    const std::vector<Vec3>* positions = nullptr, const std::vector<Field>& point_fields = {},
    const std::vector<Field>& cell_fields = {}, VtuCellTypes cell_types = VtuCellTypes::Auto);

/// As above with positions as (#N x 3) rows [m].
void write_vtu(const std::string& path, const Mesh& mesh, const MatX3& positions,
    const std::vector<Field>& point_fields = {}, const std::vector<Field>& cell_fields = {},
    VtuCellTypes cell_types = VtuCellTypes::Auto);

} // namespace polycut::mesh
