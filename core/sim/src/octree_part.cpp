// The scene's octree geometry: the object's signed value and the domain around it.
#include "octree_part.hpp"

#include "polycut/common/error.hpp"
#include "polycut/contact/triangle_mesh_distance.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/surface.hpp"

#include <filesystem>

namespace polycut::sim {
namespace {
/// The base grid of cubes of `cell_size` centred on the box [lo, hi], one cube of margin: cells
/// the surface crosses are kept whole, so the object's box is grown before rounding up.
void centre_domain(meshing::OctreeOptions& o, const Vec3& lo, const Vec3& hi) {
    const Vec3 centre = 0.5 * (lo + hi);
    const Vec3 extent = (hi - lo).array() + 2 * o.cell_size;
    Vec3 half;
    for (int a = 0; a < 3; ++a)
        half[a] = 0.5 * std::ceil(extent[a] / o.cell_size - 1e-9) * o.cell_size;
    o.lo = centre - half;
    o.hi = centre + half;
}
} // namespace

meshing::ImplicitShape implicit_shape(const scene::Geometry& g) {
    switch (g.shape) {
    case scene::Shape::Sphere:
        return meshing::ImplicitShape::sphere(g.radii.x(), g.center);
    case scene::Shape::HollowSphere:
        return meshing::ImplicitShape::hollow_sphere(g.inner_radius, g.radii.x(), g.center);
    case scene::Shape::Ellipsoid:
        return meshing::ImplicitShape::ellipsoid(g.radii, g.center);
    case scene::Shape::Capsule:
        return meshing::ImplicitShape::capsule(g.radii.x(), g.length, Vec3::UnitZ(), g.center);
    case scene::Shape::Blob:
        return meshing::ImplicitShape::blob(g.radii, g.center);
    case scene::Shape::None:
    case scene::Shape::TruncatedOctahedron:
        break;
    }
    throw SceneError("/geometry/shape", "names no implicit shape"); // the parser prevents it
}

std::unique_ptr<meshing::Octree> make_octree(const scene::Scene& s) {
    const scene::Geometry& g = s.geometry;
    meshing::OctreeOptions o;
    o.cell_size = g.cell_size;
    o.surface_cell_size = g.octree.surface_cell_size;
    o.max_depth = g.octree.max_depth;
    o.keep = g.octree.keep == scene::OctreeKeep::Cover ? meshing::OctreeOptions::Keep::Cover
                                                       : meshing::OctreeOptions::Keep::Centre;
    for (const auto& r : g.octree.regions)
        o.regions.push_back({ r.lo, r.hi, r.cell_size });
    meshing::SignedValue value;
    if (g.octree.object == scene::OctreeObject::Implicit) {
        const meshing::ImplicitShape shape = implicit_shape(g);
        const double r = meshing::bounding_radius(shape);
        centre_domain(o, shape.center.array() - r, shape.center.array() + r);
        value = [shape](const Vec3& p) { return meshing::implicit_value(shape, p); };
    } else if (g.octree.object == scene::OctreeObject::SurfaceFile) {
        std::filesystem::path path(g.path);
        if (path.is_relative() && !s.directory.empty())
            path = std::filesystem::path(s.directory) / path;
        meshing::SurfaceMesh surface = meshing::read_surface(path.string(), true);
        for (Vec3& p : surface.positions)
            p *= g.scale;
        auto distance = std::make_shared<contact::TriangleMeshDistance>(
            std::move(surface.positions), surface.triangles);
        centre_domain(o, distance->lo(), distance->hi());
        value = [distance](const Vec3& p) {
            Vec3 n;
            return distance->signed_distance(p, n);
        };
    } else {
        o.lo = g.origin;
        o.hi = g.origin + g.size;
    }
    try {
        return std::make_unique<meshing::Octree>(o, std::move(value));
    } catch (const InputError& e) {
        throw SceneError("/geometry/" + e.where(), e.problem());
    }
}

} // namespace polycut::sim
