// A detailed surface embedded in a simulation mesh (issue 15 item 2; 001 sec. 7, 003 sec. 8,
// eq. 19: each embedded vertex is a fixed linear combination sum_i W_i x_i of node positions).
// The weights are the containing cell's own basis at the vertex's rest position: P1 barycentric
// coordinates in a tet, Q1 (trilinear, inverse-mapped) in a hex, mean value or harmonic
// coordinates in a polyhedron. Every one of them reproduces linear fields, so rigid motions and
// affine deformations of the nodes move the embedded surface exactly. A vertex in no cell (the
// coarse mesh approximates the detailed surface, so some lie just outside it) takes the least-
// squares affine fit of its nearest cell's nodes: also exact for affine motions.
#pragma once

#include "polycut/basis/cell_basis.hpp"
#include "polycut/mesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace polycut::embed {

/// The embedded surface and its weights.
struct Embedding {
    std::vector<Vec3> rest; ///< vertex rest positions (#V) [m]
    std::vector<std::uint32_t> triangles; ///< (#T x 3) vertex indices, outward
    /// Vertex v is sum_k weights[k] x_{nodes[k]} over k in [offsets[v], offsets[v + 1])
    std::vector<std::uint32_t> offsets;
    std::vector<Index> nodes;
    std::vector<double> weights;
    std::vector<Index> cells; ///< the cell each vertex is embedded in (#V)
    /// Where each vertex is located (#V) [m]: its rest position, or, for a vertex on a cut
    /// (split.hpp), a point a little into the material on its own side of the cut (both copies
    /// of such a vertex share the rest position; the probe says which side's cell is theirs).
    /// Empty: the rest positions.
    std::vector<Vec3> probes;
    /// Per triangle (#T): 1 for a lip (a triangle of the cut surface, tag 2), 0 for the skin.
    /// Empty: all skin.
    std::vector<std::uint8_t> lip;
    Index outside = 0; ///< vertices in no cell, embedded by their nearest cell's affine fit
    /// Largest distance of such a vertex from its cell's bounding box [m]
    double max_outside_distance = 0;
};

/// Embeds the surface (rest positions [m], outward triangles) in `mesh` at rest, polyhedra with
/// `poly`'s basis. Throws InputError for an empty surface, an index out of range or a mesh
/// without cells.
Embedding embed_surface(const mesh::Mesh& mesh, std::vector<Vec3> positions,
    const std::vector<std::array<Index, 3>>& triangles, basis::PolyBasis poly);

/// The weights of points (rest positions [m]) alone, as embed_surface() gives its vertices
/// (no triangles): e.g. the nodes of a refined mesh in the mesh before. Throws InputError for a
/// mesh without cells.
Embedding embed_points(const mesh::Mesh& mesh, std::vector<Vec3> positions, basis::PolyBasis poly);

/// As above, but each point is located at `probes[i]` (same size) and its weights evaluated
/// at `positions[i]` in that cell: a point on a cut face takes the cell on the probe's side.
Embedding embed_points(const mesh::Mesh& mesh, std::vector<Vec3> positions,
    const std::vector<Vec3>& probes, basis::PolyBasis poly);

/// Embeds the listed vertices of `e` again in `mesh` (each located at its probe), keeping the
/// others' weights: after a cut changed the cells they were in.
void reembed(Embedding& e, const mesh::Mesh& mesh, const std::vector<std::uint32_t>& vertices,
    basis::PolyBasis poly);

/// World positions of the embedded vertices from the node positions (#N) [m], as float32
/// (#V x 3), the layout of the surface stream.
void deform(const Embedding& e, const std::vector<Vec3>& node_positions, std::vector<float>& out);

/// One vertex's world position [m].
Vec3 deformed_vertex(const Embedding& e, const std::vector<Vec3>& node_positions, std::size_t v);

} // namespace polycut::embed
