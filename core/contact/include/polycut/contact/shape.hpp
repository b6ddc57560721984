// Rigid shapes the tissue can touch (scene obstacles and client-driven tools, issue 15 item 1)
// and their signed distance: plane (a half-space), box, sphere, capsule and a closed triangle
// mesh. A shape lives in its own frame; a Pose puts it in the world.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/contact/triangle_mesh_distance.hpp"

#include <memory>

namespace polycut::contact {

/// Rigid placement of a shape: world = rotation * local + position.
struct Pose {
    Vec3 position = Vec3::Zero(); ///< [m]
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity(); ///< unit quaternion
    Vec3 to_world(const Vec3& local) const { return rotation * local + position; }
    Vec3 to_local(const Vec3& world) const { return rotation.conjugate() * (world - position); }
};

/// A rigid shape in its local frame.
struct Shape {
    enum class Kind { Plane, Box, Sphere, Capsule, TriangleMesh };
    Kind kind = Kind::Sphere;
    /// Plane: the solid is the half-space local z <= 0 (outward normal +z in the local frame;
    /// a scene plane's point and normal become the pose).
    /// Box: half edge lengths along local x, y, z [m], > 0.
    Vec3 half_extents = Vec3::Constant(0.01);
    /// Sphere, Capsule: radius [m], > 0.
    double radius = 0.005;
    /// Capsule: half the length of its axis segment, along local z from -h to +h [m], >= 0.
    double half_length = 0.01;
    /// TriangleMesh: the closed surface (local frame) and its distance structure.
    std::shared_ptr<const TriangleMeshDistance> mesh;
};

/// Signed distance of a point to a shape: phi < 0 inside, with the outward direction.
struct SignedDistance {
    double phi = 0; ///< [m], negative inside the solid
    /// Unit direction of steepest increase of phi at the point (outward), in the world frame.
    Vec3 normal = Vec3::UnitZ();
};

/// Signed distance from world point `p` to `shape` placed at `pose`. Exact for every kind
/// (the mesh through its AABB tree). `facing` (optional, world): the outward normal of the
/// tissue surface at p; inside a box, the point then leaves through the nearest face whose
/// normal opposes it (the lips of a cut coincide: a blade between them pushes each lip back
/// into its own side).
SignedDistance signed_distance(
    const Shape& shape, const Pose& pose, const Vec3& p, const Vec3* facing = nullptr);

/// World bounding box of the solid (a plane: unbounded, so lo = -inf, hi = +inf).
void world_bounds(const Shape& shape, const Pose& pose, Vec3& lo, Vec3& hi);

/// Volume of the solid [m^3] (a plane: infinity).
double volume(const Shape& shape);

} // namespace polycut::contact
