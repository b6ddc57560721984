// Implicit shapes (sphere, hollow sphere, ellipsoid, capsule, organ-like blob) and their
// tetrahedral meshes by CGAL Mesh_3 on a labeled implicit domain.
#pragma once

#include "polycut/common/types.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"

namespace polycut::meshing {

/// A solid bounded by the zero level set of a smooth function, negative inside.
struct ImplicitShape {
    enum class Kind {
        Sphere, ///< radius radii.x()
        HollowSphere, ///< between radii `inner` and radii.x() (Lame's thick-walled sphere)
        Ellipsoid, ///< semi-axes radii along x, y, z
        Capsule, ///< cylinder of radius radii.x() and length `length` along `axis`, capped by
                 ///< hemispheres (total extent length + 2 radii.x())
        Blob, ///< smooth union of three ellipsoids, liver-like; its reference shape spans
              ///< about [-1, 1] x [-0.7, 0.6] x [-0.5, 0.45] and is scaled by radii per axis
    };
    Kind kind = Kind::Sphere;
    Vec3 center = Vec3::Zero(); ///< centre [m]
    Vec3 radii = Vec3::Constant(0.05); ///< semi-axes or scale [m], all > 0
    double length = 0.1; ///< capsule cylinder length [m], >= 0
    Vec3 axis = Vec3::UnitZ(); ///< capsule axis (normalised internally)
    double inner = 0; ///< hollow sphere: cavity radius [m], in (0, radii.x())
    /// Blob blend radius in reference units: a larger value rounds the creases between lobes.
    double blend = 0.25;

    /// A sphere of radius r [m].
    static ImplicitShape sphere(double r, const Vec3& center = Vec3::Zero());
    /// A thick-walled sphere between radii a < b [m].
    static ImplicitShape hollow_sphere(double a, double b, const Vec3& center = Vec3::Zero());
    /// An ellipsoid with semi-axes a [m].
    static ImplicitShape ellipsoid(const Vec3& a, const Vec3& center = Vec3::Zero());
    /// A capsule of radius r [m] and cylinder length l [m] along axis.
    static ImplicitShape capsule(
        double r, double l, const Vec3& axis = Vec3::UnitZ(), const Vec3& center = Vec3::Zero());
    /// The organ-like blob scaled by s [m] per axis (s = 0.05 gives ~10 cm across).
    static ImplicitShape blob(
        const Vec3& s = Vec3::Constant(0.05), const Vec3& center = Vec3::Zero());
};

/// Signed distance-like value of the shape at p [m]: negative inside, zero on the surface,
/// positive outside; |value| is within a factor (max radius / min radius) of the true distance
/// near the surface.
double implicit_value(const ImplicitShape& shape, const Vec3& p);

/// Radius of a ball around shape.center that contains the whole shape [m].
double bounding_radius(const ImplicitShape& shape);

/// A volume estimate with a guaranteed error bound.
struct VolumeEstimate {
    double volume = 0; ///< [m^3]
    double error_bound = 0; ///< |volume - true volume| <= error_bound [m^3]
};

/// Midpoint rule on the indicator of the shape over a grid of 2^depth cells per axis covering the
/// bounding cube, evaluated adaptively: since implicit_value() is 1-Lipschitz, an octree block
/// whose centre value exceeds its half-diagonal is entirely inside or outside and is counted
/// whole (same result as the full grid, cost ~ surface cells). The bound is the volume of the
/// finest cells the surface may cross.
VolumeEstimate estimate_implicit_volume(const ImplicitShape& shape, int depth = 8);

/// Exact volume [m^3] for Sphere, HollowSphere, Ellipsoid and Capsule; for Blob,
/// estimate_implicit_volume().
double implicit_volume(const ImplicitShape& shape);

/// Throws InputError if the shape has non-positive or non-finite radii, a negative length or a
/// zero capsule axis.
void check_shape(const ImplicitShape& shape);

/// Tetrahedral mesh of the shape (CGAL Mesh_3, labeled implicit domain). Positions in metres;
/// unreferenced vertices are dropped; tets are positively oriented. Deterministic for a given
/// options.seed. Reports each Mesh_3 phase and the tets' quality to `progress` (e.g.
/// print_progress; empty: silent). Throws InputError for a bad shape or options, MeshError if
/// CGAL produced no cell.
mesh::Mesh mesh_implicit(
    const ImplicitShape& shape, const MeshingOptions& options, const ProgressSink& progress = {});

} // namespace polycut::meshing
