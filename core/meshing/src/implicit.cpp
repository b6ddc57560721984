// Tetrahedral meshes of implicit shapes: CGAL Mesh_3 on a labeled implicit domain.
#include "polycut/meshing/implicit.hpp"

#include "mesh3_common.hpp"
#include "polycut/meshing/quality.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <functional>

namespace polycut::meshing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;

} // namespace

mesh::Mesh mesh_implicit(
    const ImplicitShape& shape, const MeshingOptions& options, const ProgressSink& progress) {
    check_shape(shape);
    check_options(options);
    // Surface points are found by bisection on segments until they are shorter than
    // relative_error_bound x the bounding sphere's diameter (1e-6: ~0.1 um for a 10 cm organ).
    const std::function<double(const Point&)> value
        = [shape](const Point& p) { return implicit_value(shape, Vec3(p.x(), p.y(), p.z())); };
    // The bounding sphere must strictly contain the shape; 20 % margin. Mesh_3 finds its first
    // surface points on segments from the sphere's centre outward, so the centre must lie inside
    // the shape: for a hollow sphere, in the middle of the wall.
    Vec3 centre = shape.center;
    double R = 1.2 * bounding_radius(shape);
    if (shape.kind == ImplicitShape::Kind::HollowSphere) {
        const double mid = 0.5 * (shape.inner + shape.radii.x());
        centre += Vec3(mid, 0, 0);
        R += 1.2 * mid;
    }
    const Point c(centre.x(), centre.y(), centre.z());
    CGAL::Random rng(options.seed);
    namespace p = CGAL::parameters;
    const Domain domain = Domain::create_implicit_mesh_domain(
        value, Kernel::Sphere_3(c, R * R), p::relative_error_bound = 1e-6, p::p_rng = &rng);
    const C3t3 c3t3 = detail::run_mesh_3<C3t3>(domain, options, 8 * R * R * R, progress);
    mesh::Mesh m = detail::to_mesh(c3t3, "implicit shape");
    if (progress)
        progress("quality: " + to_string(tet_quality(m)));
    return m;
}

} // namespace polycut::meshing
