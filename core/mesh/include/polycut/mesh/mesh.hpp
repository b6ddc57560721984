// The polyhedral mesh: nodes with rest positions, cells as polyhedra of planar polygon faces,
// and a global face table with owner/neighbour adjacency (as OpenFOAM's polyMesh). Every interior
// face is shared by exactly two cells; a face of one cell is never partly covered by another's
// (a cut that splits a face splits it in both cells, so hanging nodes live on edges only).
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace polycut::mesh {

/// What basis a cell can use: tets are P1, hexes Q1, everything else a polyhedral basis.
enum class CellShape : std::uint8_t { Tet, Hex, Polyhedron };

/// Tag of a face: interior, the original skin of the tissue, or a surface made by a cut.
enum class FaceTag : std::uint8_t { Interior = 0, Skin = 1, Cut = 2 };

/// A planar polygon face.
struct Face {
    std::vector<Index> nodes;      ///< loop, outward for `owner` (right-hand rule)
    Index owner = kNone;           ///< cell for which the loop is outward
    Index neighbour = kNone;       ///< cell on the other side, kNone on the boundary
    FaceTag tag = FaceTag::Skin;   ///< Interior iff neighbour != kNone
    Index parent = kNone;          ///< face this one was split from by a cut, kNone otherwise
    bool boundary() const { return neighbour == kNone; }
};

/// A polyhedral cell.
struct Cell {
    /// Distinct nodes of the cell. Tet: 4 nodes, VTK order, positive orientation. Hex: 8 nodes,
    /// VTK order (bottom loop counter-clockwise seen from +z over it, then top). Polyhedron:
    /// any order.
    std::vector<Index> nodes;
    std::vector<Index> faces;      ///< global face ids
    CellShape shape = CellShape::Polyhedron;
    Index parent = kNone;          ///< cell this one was split from, kNone otherwise
};

/// Outward face loops of the VTK tet (0,1,2,3) and hex (0..7), as local node numbers.
inline constexpr std::array<std::array<int, 3>, 4> kTetFaces { { { 0, 2, 1 }, { 0, 1, 3 },
    { 1, 2, 3 }, { 0, 3, 2 } } };
inline constexpr std::array<std::array<int, 4>, 6> kHexFaces { { { 0, 3, 2, 1 }, { 4, 5, 6, 7 },
    { 0, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 }, { 3, 0, 4, 7 } } };

/// A polyhedral mesh. Fields are public so the cutter can edit them; after editing, the
/// invariants above must hold (validate() checks them).
class Mesh {
public:
    std::vector<Vec3> rest;  ///< rest positions X (#N) [m]
    std::vector<Face> faces; ///< global face table
    std::vector<Cell> cells; ///< cells

    /// Tetrahedra in VTK order. Inverted tets are reordered to positive orientation.
    static Mesh from_tets(std::vector<Vec3> rest, const std::vector<std::array<Index, 4>>& tets);
    /// Hexahedra in VTK order.
    static Mesh from_hexes(std::vector<Vec3> rest, const std::vector<std::array<Index, 8>>& hexes);
    /// General polyhedra, each given as outward face loops. Faces of two cells with the same
    /// node set are matched as one interior face. Throws MeshError if three or more cells claim
    /// one face or a cell repeats a face.
    static Mesh from_polyhedra(std::vector<Vec3> rest,
        const std::vector<std::vector<std::vector<Index>>>& cells);

    Index num_nodes() const { return Index(rest.size()); }
    Index num_cells() const { return Index(cells.size()); }
    Index num_faces() const { return Index(faces.size()); }

    /// Loop of face f oriented outward as seen from cell c (reversed for the neighbour).
    std::vector<Index> face_loop(Index f, Index c) const;
    /// All outward face loops of cell c.
    std::vector<std::vector<Index>> cell_face_loops(Index c) const;
    /// Rest volume of cell c [m^3] (divergence theorem).
    double cell_volume(Index c) const;
    /// Rest centroid of cell c [m].
    Vec3 cell_centroid(Index c) const;
    /// Total rest volume [m^3].
    double rest_volume() const;
    /// Ids of boundary faces (skin and cut).
    std::vector<Index> boundary_faces() const;
    /// Number of boundary triangles when each boundary face is fanned (k-2 per k-gon).
    Index num_boundary_triangles() const;
    /// For each node, the cells that use it.
    std::vector<std::vector<Index>> node_cells() const;
    /// Number of connected components of cells (through shared nodes).
    Index count_components() const;

    /// Recomputes the shape of cell c from its faces (4 triangles -> Tet, 6 quads in hex
    /// arrangement -> Hex, else Polyhedron); for Tet/Hex also puts `nodes` in VTK order.
    void classify_cell(Index c);
};

} // namespace polycut::mesh
