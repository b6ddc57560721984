// Implicit shape functions (no CGAL): distance-like values, bounds and volumes.
#include "polycut/common/error.hpp"
#include "polycut/meshing/implicit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace polycut::meshing {

namespace {

/// Distance-like function of an ellipsoid with semi-axes r centred at the origin, evaluated
/// at q: (|q / r| - 1) min(r). Exact for a sphere, 1-Lipschitz, same zero set as the
/// ellipsoid.
double ellipsoid_value(const Vec3& q, const Vec3& r) {
    // Scalar code: this runs ~10^6 times per volume estimate, and unoptimised Eigen
    // expressions (Debug + sanitizers) are an order of magnitude slower.
    const double x = q[0] / r[0], y = q[1] / r[1], z = q[2] / r[2];
    return (std::sqrt(x * x + y * y + z * z) - 1) * std::min({ r[0], r[1], r[2] });
}

/// Quadratic polynomial smooth minimum with blend width k (Quilez): equals min(a, b) when
/// |a - b| >= k and lies at most k / 4 below it.
double smooth_min(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - 0.25 * h * h * k;
}

/// The three lobes of the blob in reference units (centre, semi-axes): a large right lobe, a
/// flatter left lobe and a caudate-like lobe underneath, roughly a liver.
struct Lobe {
    Vec3 center;
    Vec3 radii;
};
const Lobe kBlobLobes[3] = {
    { Vec3(-0.2, 0.0, 0.0), Vec3(0.8, 0.55, 0.4) },
    { Vec3(0.45, 0.1, 0.05), Vec3(0.55, 0.4, 0.3) },
    { Vec3(-0.1, -0.35, -0.1), Vec3(0.45, 0.35, 0.35) },
};

Vec3 unit_axis(const ImplicitShape& shape) {
    return shape.axis.normalized();
}

} // namespace

ImplicitShape ImplicitShape::sphere(double r, const Vec3& center) {
    ImplicitShape s;
    s.kind = Kind::Sphere;
    s.center = center;
    s.radii = Vec3::Constant(r);
    return s;
}

ImplicitShape ImplicitShape::hollow_sphere(double a, double b, const Vec3& center) {
    ImplicitShape s;
    s.kind = Kind::HollowSphere;
    s.center = center;
    s.radii = Vec3::Constant(b);
    s.inner = a;
    return s;
}

ImplicitShape ImplicitShape::ellipsoid(const Vec3& a, const Vec3& center) {
    ImplicitShape s;
    s.kind = Kind::Ellipsoid;
    s.center = center;
    s.radii = a;
    return s;
}

ImplicitShape ImplicitShape::capsule(double r, double l, const Vec3& axis, const Vec3& center) {
    ImplicitShape s;
    s.kind = Kind::Capsule;
    s.center = center;
    s.radii = Vec3::Constant(r);
    s.length = l;
    s.axis = axis;
    return s;
}

ImplicitShape ImplicitShape::blob(const Vec3& scale, const Vec3& center) {
    ImplicitShape s;
    s.kind = Kind::Blob;
    s.center = center;
    s.radii = scale;
    return s;
}

void check_shape(const ImplicitShape& shape) {
    if (!shape.center.allFinite())
        throw InputError("shape.center", "centre must be finite");
    if (!shape.radii.allFinite() || shape.radii.minCoeff() <= 0)
        throw InputError("shape.radii", "radii must be finite and > 0");
    if (shape.kind == ImplicitShape::Kind::Capsule) {
        if (!std::isfinite(shape.length) || shape.length < 0)
            throw InputError("shape.length", "capsule length must be finite and >= 0");
        if (!shape.axis.allFinite() || shape.axis.norm() == 0)
            throw InputError("shape.axis", "capsule axis must be finite and non-zero");
    }
    if (shape.kind == ImplicitShape::Kind::HollowSphere
        && !(std::isfinite(shape.inner) && shape.inner > 0 && shape.inner < shape.radii.x()))
        throw InputError("shape.inner", "cavity radius must be in (0, radius)");
    if (shape.kind == ImplicitShape::Kind::Blob && !(shape.blend > 0 && shape.blend < 1))
        throw InputError("shape.blend", "blob blend must be in (0, 1)");
}

double implicit_value(const ImplicitShape& shape, const Vec3& p) {
    const Vec3 q = p - shape.center;
    switch (shape.kind) {
    case ImplicitShape::Kind::Sphere:
        return q.norm() - shape.radii.x();
    case ImplicitShape::Kind::HollowSphere: {
        const double r = q.norm();
        return std::max(r - shape.radii.x(), shape.inner - r);
    }
    case ImplicitShape::Kind::Ellipsoid:
        return ellipsoid_value(q, shape.radii);
    case ImplicitShape::Kind::Capsule: {
        // Distance to the axis segment [-l/2, l/2] minus the radius.
        const Vec3 a = unit_axis(shape);
        const double t = std::clamp(q.dot(a), -0.5 * shape.length, 0.5 * shape.length);
        return (q - t * a).norm() - shape.radii.x();
    }
    case ImplicitShape::Kind::Blob: {
        const Vec3& s = shape.radii;
        double v = 0;
        for (int i = 0; i < 3; ++i) {
            const Lobe& lobe = kBlobLobes[i];
            const Vec3 u(q[0] / s[0] - lobe.center[0], q[1] / s[1] - lobe.center[1],
                q[2] / s[2] - lobe.center[2]);
            const double vi = ellipsoid_value(u, lobe.radii);
            v = i == 0 ? vi : smooth_min(v, vi, shape.blend);
        }
        return v * std::min({ s[0], s[1], s[2] });
    }
    }
    return 1.0;
}

double bounding_radius(const ImplicitShape& shape) {
    switch (shape.kind) {
    case ImplicitShape::Kind::Sphere:
    case ImplicitShape::Kind::HollowSphere:
        return shape.radii.x();
    case ImplicitShape::Kind::Ellipsoid:
        return shape.radii.maxCoeff();
    case ImplicitShape::Kind::Capsule:
        return 0.5 * shape.length + shape.radii.x();
    case ImplicitShape::Kind::Blob: {
        // Each lobe lies within |centre| + max radius of the reference origin; the smooth union
        // adds at most blend / 4 (in units of the lobe's distance function, <= reference units).
        double r = 0;
        for (const Lobe& lobe : kBlobLobes)
            r = std::max(r, lobe.center.norm() + lobe.radii.maxCoeff());
        return (r + 0.25 * shape.blend) * shape.radii.maxCoeff();
    }
    }
    return 0;
}

namespace {

/// Octree recursion of estimate_implicit_volume(): block with centre c and half-size h.
void count_block(
    const ImplicitShape& shape, const Vec3& c, double h, int depth, VolumeEstimate& out) {
    const double f = implicit_value(shape, c);
    const double cube = 8 * h * h * h;
    if (depth == 0) {
        if (f < 0)
            out.volume += cube;
        if (std::abs(f) <= std::sqrt(3.0) * h)
            out.error_bound += cube;
        return;
    }
    if (std::abs(f) > std::sqrt(3.0) * h) { // 1-Lipschitz: no sign change in the block
        if (f < 0)
            out.volume += cube;
        return;
    }
    for (int k = 0; k < 8; ++k) {
        const Vec3 offset((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
        count_block(shape, c + h * offset, 0.5 * h, depth - 1, out);
    }
}

} // namespace

VolumeEstimate estimate_implicit_volume(const ImplicitShape& shape, int depth) {
    check_shape(shape);
    VolumeEstimate out;
    // Slightly larger than the bounding ball so that no part of the shape touches the border.
    count_block(shape, shape.center, 1.01 * bounding_radius(shape), std::clamp(depth, 0, 12), out);
    return out;
}

double implicit_volume(const ImplicitShape& shape) {
    constexpr double pi = std::numbers::pi;
    switch (shape.kind) {
    case ImplicitShape::Kind::Sphere:
        return 4.0 / 3.0 * pi * std::pow(shape.radii.x(), 3);
    case ImplicitShape::Kind::HollowSphere:
        return 4.0 / 3.0 * pi * (std::pow(shape.radii.x(), 3) - std::pow(shape.inner, 3));
    case ImplicitShape::Kind::Ellipsoid:
        return 4.0 / 3.0 * pi * shape.radii.prod();
    case ImplicitShape::Kind::Capsule: {
        const double r = shape.radii.x();
        return pi * r * r * shape.length + 4.0 / 3.0 * pi * r * r * r;
    }
    case ImplicitShape::Kind::Blob:
        break;
    }
    return estimate_implicit_volume(shape).volume;
}

} // namespace polycut::meshing
