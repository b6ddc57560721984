// Signed distance to a closed triangle surface through CGAL's AABB tree (closest point) and
// Side_of_triangle_mesh (inside test). CGAL stays in triangle_mesh_distance.cpp.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <memory>
#include <vector>

namespace polycut::contact {

class TriangleMeshDistance {
public:
    /// Builds the tree. `positions` (#V) [m], `triangles` (#T x 3) vertex ids of a closed,
    /// consistently oriented surface (meshing::read_surface with require_closed checks it).
    /// Throws InputError on an empty surface or an id out of range.
    TriangleMeshDistance(
        std::vector<Vec3> positions, const std::vector<std::array<Index, 3>>& triangles);
    ~TriangleMeshDistance();
    TriangleMeshDistance(const TriangleMeshDistance&) = delete;
    TriangleMeshDistance& operator=(const TriangleMeshDistance&) = delete;

    /// Signed distance [m] (negative inside) and the unit outward direction at `p`: from the
    /// point to its closest surface point (inside: away from it), the closest triangle's normal
    /// when the point lies on the surface.
    double signed_distance(const Vec3& p, Vec3& normal) const;
    /// Bounding box of the vertices.
    const Vec3& lo() const { return m_lo; }
    const Vec3& hi() const { return m_hi; }
    /// Enclosed volume [m^3].
    double volume() const { return m_volume; }
    std::size_t num_triangles() const { return m_num_triangles; }

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    Vec3 m_lo, m_hi;
    double m_volume = 0;
    std::size_t m_num_triangles = 0;
};

} // namespace polycut::contact
