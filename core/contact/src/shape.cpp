// Signed distances and bounds of the rigid shapes (shape.hpp).
#include "polycut/contact/shape.hpp"

#include <cmath>
#include <limits>

namespace polycut::contact {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Signed distance to the box [-h, h] in its frame (the usual exact box SDF), with the outward
/// direction: outside, from the closest point; inside, the axis of the nearest face.
double box_distance(const Vec3& h, const Vec3& p, const Vec3* facing, Vec3& n) {
    const Vec3 q = p.cwiseAbs() - h;
    const Vec3 sign = p.unaryExpr([](double x) { return x < 0 ? -1.0 : 1.0; });
    if ((q.array() > 0).any()) {
        const Vec3 out = q.cwiseMax(0.0);
        const double d = out.norm();
        n = out.cwiseProduct(sign) / d;
        return d;
    }
    // Inside: the nearest face, or with `facing` the nearest face whose outward normal opposes
    // it (a thin blade between the coincident lips of a cut: each lip leaves through the face
    // it faces, not both through whichever is a round-off nearer).
    double best = -std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis)
        for (const double side : { -1.0, 1.0 }) {
            const double d = side * p[axis] - h[axis]; // <= 0 inside
            if (facing && side * (*facing)[axis] >= 0)
                continue;
            if (d > best) {
                best = d;
                n = Vec3::Zero();
                n[axis] = side;
            }
        }
    if (best > -std::numeric_limits<double>::infinity())
        return best;
    Index axis = 0;
    const double d = q.maxCoeff(&axis);
    n = Vec3::Zero();
    n[axis] = sign[axis];
    return d;
}

/// Distance to a sphere of radius r at the origin; the direction is +z at the very centre.
double ball_distance(double r, const Vec3& p, Vec3& n) {
    const double len = p.norm();
    n = len > 0 ? Vec3(p / len) : Vec3::UnitZ();
    return len - r;
}
} // namespace

SignedDistance signed_distance(
    const Shape& shape, const Pose& pose, const Vec3& p, const Vec3* facing) {
    const Vec3 local = pose.to_local(p);
    Vec3 facing_local;
    if (facing)
        facing_local = pose.rotation.conjugate() * *facing;
    SignedDistance out;
    Vec3 n = Vec3::UnitZ();
    switch (shape.kind) {
    case Shape::Kind::Plane:
        out.phi = local.z();
        break;
    case Shape::Kind::Box:
        out.phi = box_distance(shape.half_extents, local, facing ? &facing_local : nullptr, n);
        break;
    case Shape::Kind::Sphere:
        out.phi = ball_distance(shape.radius, local, n);
        break;
    case Shape::Kind::Capsule: {
        // Distance to the axis segment [-h, h] along z, minus the radius.
        const double z = std::clamp(local.z(), -shape.half_length, shape.half_length);
        out.phi = ball_distance(shape.radius, local - Vec3(0, 0, z), n);
        if (local.head<2>().norm() == 0 && std::abs(local.z()) < shape.half_length)
            n = Vec3::UnitX(); // on the axis: any radial direction
        break;
    }
    case Shape::Kind::TriangleMesh:
        out.phi = shape.mesh ? shape.mesh->signed_distance(local, n) : kInf;
        break;
    }
    out.normal = pose.rotation * n;
    return out;
}

void world_bounds(const Shape& shape, const Pose& pose, Vec3& lo, Vec3& hi) {
    Vec3 llo = Vec3::Zero(), lhi = Vec3::Zero();
    switch (shape.kind) {
    case Shape::Kind::Plane:
        lo = Vec3::Constant(-kInf);
        hi = Vec3::Constant(kInf);
        return;
    case Shape::Kind::Box:
        lhi = shape.half_extents;
        llo = -lhi;
        break;
    case Shape::Kind::Sphere:
        lo = pose.position - Vec3::Constant(shape.radius);
        hi = pose.position + Vec3::Constant(shape.radius);
        return;
    case Shape::Kind::Capsule:
        lhi = Vec3(shape.radius, shape.radius, shape.half_length + shape.radius);
        llo = -lhi;
        break;
    case Shape::Kind::TriangleMesh:
        llo = shape.mesh ? shape.mesh->lo() : Vec3::Zero();
        lhi = shape.mesh ? shape.mesh->hi() : Vec3::Zero();
        break;
    }
    // The rotated local box: centre plus |R| times the half extent.
    const Mat3 R = pose.rotation.toRotationMatrix();
    const Vec3 c = pose.to_world(0.5 * (llo + lhi));
    const Vec3 e = R.cwiseAbs() * (0.5 * (lhi - llo));
    lo = c - e;
    hi = c + e;
}

double volume(const Shape& shape) {
    constexpr double pi = 3.14159265358979323846;
    switch (shape.kind) {
    case Shape::Kind::Plane:
        return kInf;
    case Shape::Kind::Box:
        return 8 * shape.half_extents.prod();
    case Shape::Kind::Sphere:
        return 4.0 / 3.0 * pi * std::pow(shape.radius, 3);
    case Shape::Kind::Capsule:
        return 4.0 / 3.0 * pi * std::pow(shape.radius, 3)
            + pi * shape.radius * shape.radius * 2 * shape.half_length;
    case Shape::Kind::TriangleMesh:
        return shape.mesh ? shape.mesh->volume() : 0.0;
    }
    return 0;
}

} // namespace polycut::contact
