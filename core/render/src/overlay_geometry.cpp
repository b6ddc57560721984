// Cylinders, cones, arrows, spheres, capsules and boxes as lit triangles, for the scalpel blade,
// force arrows and rigid tools.
#include "overlay_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace polycut::render {

std::array<std::uint8_t, 4> to_rgba8(const std::array<float, 3>& rgb) {
    std::array<std::uint8_t, 4> out {};
    for (int c = 0; c < 3; ++c)
        out[c] = static_cast<std::uint8_t>(std::lround(std::clamp(rgb[c], 0.0f, 1.0f) * 255.0f));
    out[3] = 255;
    return out;
}

namespace {

/// Two unit vectors orthogonal to `axis` (unit) and to each other.
std::pair<Vec3, Vec3> basis_around(const Vec3& axis) {
    const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 u = axis.cross(helper).normalized();
    return { u, axis.cross(u) };
}

std::uint32_t push(
    LitGeometry& out, const Vec3& p, const Vec3& n, const std::array<std::uint8_t, 4>& colour) {
    LitVertex v {};
    for (int c = 0; c < 3; ++c) {
        v.position[c] = static_cast<float>(p[c]);
        v.normal[c] = static_cast<float>(n[c]);
    }
    std::copy(colour.begin(), colour.end(), v.colour);
    out.vertices.push_back(v);
    return static_cast<std::uint32_t>(out.vertices.size() - 1);
}

void append_disc(const Vec3& centre, const Vec3& normal, const Vec3& u, const Vec3& w,
    double radius, const std::array<std::uint8_t, 4>& colour, LitGeometry& out, int segments) {
    const std::uint32_t middle = push(out, centre, normal, colour);
    const std::uint32_t first = static_cast<std::uint32_t>(out.vertices.size());
    for (int i = 0; i < segments; ++i) {
        const double phi = 2 * std::numbers::pi * i / segments;
        push(out, centre + radius * (std::cos(phi) * u + std::sin(phi) * w), normal, colour);
    }
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t a = first + i, b = first + (i + 1) % segments;
        // Two-sided lighting in the shader makes the winding irrelevant.
        out.indices.insert(out.indices.end(), { middle, a, b });
    }
}

} // namespace

void append_cylinder(const Vec3& a, const Vec3& b, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int segments) {
    const Vec3 d = b - a;
    if (!(d.norm() > 0) || !(radius > 0))
        return;
    const Vec3 axis = d.normalized();
    const auto [u, w] = basis_around(axis);
    const std::uint32_t first = static_cast<std::uint32_t>(out.vertices.size());
    for (int i = 0; i < segments; ++i) {
        const double phi = 2 * std::numbers::pi * i / segments;
        const Vec3 n = std::cos(phi) * u + std::sin(phi) * w;
        push(out, a + radius * n, n, colour);
        push(out, b + radius * n, n, colour);
    }
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t a0 = first + 2 * i, b0 = a0 + 1;
        const std::uint32_t a1 = first + 2 * ((i + 1) % segments), b1 = a1 + 1;
        out.indices.insert(out.indices.end(), { a0, a1, b1, a0, b1, b0 });
    }
    append_disc(a, -axis, u, w, radius, colour, out, segments);
    append_disc(b, axis, u, w, radius, colour, out, segments);
}

void append_cone(const Vec3& base, const Vec3& tip, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int segments) {
    const Vec3 d = tip - base;
    const double height = d.norm();
    if (!(height > 0) || !(radius > 0))
        return;
    const Vec3 axis = d / height;
    const auto [u, w] = basis_around(axis);
    const std::uint32_t first = static_cast<std::uint32_t>(out.vertices.size());
    for (int i = 0; i < segments; ++i) {
        const double phi = 2 * std::numbers::pi * i / segments;
        const Vec3 radial = std::cos(phi) * u + std::sin(phi) * w;
        // Surface normal of the cone: tilted from radial towards the axis by the half angle.
        const Vec3 n = (height * radial + radius * axis).normalized();
        push(out, base + radius * radial, n, colour);
        push(out, tip, n, colour);
    }
    for (int i = 0; i < segments; ++i) {
        const std::uint32_t r0 = first + 2 * i, t0 = r0 + 1;
        const std::uint32_t r1 = first + 2 * ((i + 1) % segments);
        out.indices.insert(out.indices.end(), { r0, r1, t0 });
    }
    append_disc(base, -axis, u, w, radius, colour, out, segments);
}

void append_arrow(const Vec3& origin, const Vec3& vector, double radius,
    std::array<std::uint8_t, 4> colour, LitGeometry& out) {
    const double length = vector.norm();
    if (!(length > 0) || !(radius > 0))
        return;
    const double head = std::min(0.35 * length, 7 * radius);
    const Vec3 neck = origin + (1 - head / length) * vector;
    append_cylinder(origin, neck, radius, colour, out);
    append_cone(neck, origin + vector, 2.5 * radius, colour, out);
}

void append_sphere(const Vec3& centre, double radius, const Mat3& rotation,
    std::array<std::uint8_t, 4> colour, LitGeometry& out, int rings, int segments) {
    if (!(radius > 0))
        return;
    const std::uint32_t first = static_cast<std::uint32_t>(out.vertices.size());
    for (int i = 0; i <= rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j <= segments; ++j) {
            const double phi = 2 * std::numbers::pi * j / segments;
            const Vec3 n = rotation
                * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                    std::cos(theta));
            push(out, centre + radius * n, n, colour);
        }
    }
    const std::uint32_t row = static_cast<std::uint32_t>(segments + 1);
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const std::uint32_t a = first + i * row + j, b = a + row;
            out.indices.insert(out.indices.end(), { a, b, b + 1, a, b + 1, a + 1 });
        }
}

void append_capsule(const Vec3& a, const Vec3& b, double radius, std::array<std::uint8_t, 4> colour,
    LitGeometry& out) {
    if (!(radius > 0))
        return;
    append_cylinder(a, b, radius, colour, out, 24);
    append_sphere(a, radius, Mat3::Identity(), colour, out);
    append_sphere(b, radius, Mat3::Identity(), colour, out);
}

void append_box(const Vec3& centre, const Vec3& size, const Mat3& rotation,
    std::array<std::uint8_t, 4> colour, LitGeometry& out) {
    if (!(size.minCoeff() > 0))
        return;
    const Vec3 half = 0.5 * size;
    for (int axis = 0; axis < 3; ++axis)
        for (const int sign : { -1, 1 }) {
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            const Vec3 n = sign * rotation.col(axis);
            const Vec3 c = centre + sign * half[axis] * rotation.col(axis);
            const Vec3 u = half[a1] * rotation.col(a1), w = half[a2] * rotation.col(a2);
            const std::uint32_t first = static_cast<std::uint32_t>(out.vertices.size());
            push(out, c - u - w, n, colour);
            push(out, c + u - w, n, colour);
            push(out, c + u + w, n, colour);
            push(out, c - u + w, n, colour);
            // Counter-clockwise seen from outside (back faces may be culled).
            if (sign > 0)
                out.indices.insert(out.indices.end(),
                    { first, first + 1, first + 2, first, first + 2, first + 3 });
            else
                out.indices.insert(out.indices.end(),
                    { first, first + 2, first + 1, first, first + 3, first + 2 });
        }
}

} // namespace polycut::render
