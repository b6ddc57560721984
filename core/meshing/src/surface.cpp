// Tetrahedral meshes of the volume bounded by a closed triangle surface: CGAL Mesh_3 on a
// polyhedral domain with sharp features.
#include "polycut/meshing/surface.hpp"

#include "mesh3_common.hpp"
#include "surface_prepare.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Surface_mesh.h>
#include <Eigen/Geometry>
#include <cstddef>

namespace polycut::meshing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Polyhedron = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<Kernel, Polyhedron>;
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation, Domain::Corner_index,
    Domain::Curve_index>;

} // namespace

mesh::Mesh detail::mesh_prepared_surface(
    const SurfaceMesh& s, const MeshingOptions& options, const ProgressSink& sink) {
    Polyhedron poly;
    std::vector<Polyhedron::Vertex_index> v;
    v.reserve(s.positions.size());
    for (const Vec3& p : s.positions)
        v.push_back(poly.add_vertex(Point(p.x(), p.y(), p.z())));
    for (const auto& t : s.triangles)
        poly.add_face(v[std::size_t(t[0])], v[std::size_t(t[1])], v[std::size_t(t[2])]);
    CGAL::Random rng(options.seed);
    Domain domain(poly, &rng);
    if (options.feature_angle > 0)
        domain.detect_features(options.feature_angle);
    Eigen::AlignedBox3d box;
    for (const Vec3& p : s.positions)
        box.extend(p);
    const C3t3 c3t3 = detail::run_mesh_3<C3t3>(domain, options, box.volume(), sink);
    return detail::to_mesh(c3t3, "surface");
}

mesh::Mesh mesh_surface(const SurfaceMesh& surface, const MeshingOptions& options) {
    check_options(options);
    SurfaceMesh s = surface;
    if (std::string problem = detail::prepare_closed_surface(s); !problem.empty())
        throw InputError("surface", problem);
    return detail::mesh_prepared_surface(s, options);
}

} // namespace polycut::meshing
