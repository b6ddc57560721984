// Private: triangle geometry for the scalpel blade and force arrows, and the interleaved vertex
// formats the renderer uploads.
#pragma once

#include "polycut/common/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace polycut::render {

/// A lit vertex: position [m], unit normal, RGBA8 colour (28 bytes, interleaved).
struct LitVertex {
    float position[3];
    float normal[3];
    std::uint8_t colour[4];
};

/// An unlit line vertex: position [m], RGBA8 colour.
struct LineVertex {
    float position[3];
    std::uint8_t colour[4];
};

/// Triangles to append to: vertices and (#T x 3) indices into them.
struct LitGeometry {
    std::vector<LitVertex> vertices;
    std::vector<std::uint32_t> indices;
};

/// RGBA8 of a colour in [0, 1]^3, opaque.
std::array<std::uint8_t, 4> to_rgba8(const std::array<float, 3>& rgb);

/// Appends a capped cylinder of `radius` [m] from a to b [m] with `segments` sides.
void append_cylinder(const Vec3& a, const Vec3& b, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int segments = 16);

/// Appends a cone with base disc at `base` of `radius` [m] and apex at `tip` [m].
void append_cone(const Vec3& base, const Vec3& tip, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int segments = 16);

/// Appends an arrow from `origin` to `origin + vector` [m]: a shaft of `radius` and a cone head.
void append_arrow(const Vec3& origin, const Vec3& vector, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out);

/// Appends a UV sphere of `radius` [m] about `centre` [m]; `rotation` turns its poles (local z).
void append_sphere(const Vec3& centre, double radius, const Mat3& rotation,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int rings = 12, int segments = 24);

/// Appends a capsule: a cylinder of `radius` [m] from a to b [m] with hemispherical caps.
void append_capsule(const Vec3& a, const Vec3& b, double radius, std::array<std::uint8_t, 4> colour,
    LitGeometry& out);

/// Appends a box of edge lengths `size` [m] (local x, y, z) centred at `centre`, its axes the
/// columns of `rotation`, with flat faces.
void append_box(const Vec3& centre, const Vec3& size, const Mat3& rotation,
    std::array<std::uint8_t, 4> colour, LitGeometry& out);

} // namespace polycut::render
