// The surface users see: the mesh's boundary faces (skin and cut) as a triangle soup with
// compact vertex numbering, ready for streaming and rendering (DESIGN.md sec. 3).
#pragma once

#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace polycut::surface {

/// Per-triangle tag on the wire and in the renderer.
enum class Tag : std::uint8_t { Skin = 1, Cut = 2 };

/// Boundary topology: which mesh nodes are surface vertices, and the triangles over them.
struct Topology {
    std::vector<Index> vertex_nodes; ///< mesh node of each surface vertex (#V)
    std::vector<std::uint32_t> triangles; ///< (#T x 3) indices into the surface vertices
    std::vector<std::uint8_t> tags; ///< (#T) Tag per triangle
    std::vector<Index> triangle_faces; ///< (#T) mesh face each triangle comes from
};

/// Triangulates every boundary face (a fan around its first node; boundary faces are convex
/// polygons, possibly with collinear nodes, whose zero-area fan triangles are skipped) with the
/// outward orientation of its cell.
Topology extract_topology(const mesh::Mesh& mesh);

/// Positions (#V x 3, float32) [m] of the surface vertices, from per-node world positions.
void gather_positions(
    const Topology& topo, const std::vector<Vec3>& node_positions, std::vector<float>& out);

/// True when every edge of the triangles is shared by exactly two triangles in opposite
/// directions (closed, consistently oriented 2-manifold).
bool is_closed_oriented(const Topology& topo);

} // namespace polycut::surface
