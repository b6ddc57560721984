// Tetrahedral meshes of implicit shapes (CGAL Mesh_3): validity, volume against the analytic or
// a grid-estimated value within the tolerance the facet criteria imply, boundary on the surface,
// determinism for a fixed seed.
#include "polycut/common/error.hpp"
#include "polycut/mesh/validate.hpp"
#include "polycut/meshing/implicit.hpp"
#include "polycut/meshing/quality.hpp"
#include "polycut/meshing/surface.hpp"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <numbers>

using namespace polycut;
using namespace polycut::meshing;

namespace {

/// Circumcentre of a 3D triangle.
Vec3 circumcentre(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = b - a, v = c - a, n = u.cross(v);
    return a
        + (u.squaredNorm() * v.cross(n) + v.squaredNorm() * n.cross(u)) / (2 * n.squaredNorm());
}

double surface_area(const SurfaceMesh& s) {
    double area = 0;
    for (const auto& t : s.triangles) {
        const Vec3& a = s.positions[std::size_t(t[0])];
        area += 0.5
            * (s.positions[std::size_t(t[1])] - a).cross(s.positions[std::size_t(t[2])] - a).norm();
    }
    return area;
}

/// The plain refined mesh: the facet criteria below are guarantees of Mesh_3's refinement;
/// sliver perturbation and exudation (on by default) move vertices and weights afterwards and
/// may leave a boundary facet up to ~1.4 d from the surface (MeshImplicit.DefaultOptimisers).
MeshingOptions coarse(double cell_size) {
    MeshingOptions o;
    o.cell_size = cell_size;
    o.perturb = false;
    o.exude = false;
    return o;
}

/// Checks shared by every shape; returns the mesh volume [m^3].
///  - check_mesh finds nothing: every tet has positive volume, the face table is consistent, no
///    unused or duplicate nodes, and the skin is a closed oriented 2-manifold;
///  - every boundary vertex lies on the surface: |f| <= 1e-5 R (f is 1-Lipschitz and CGAL's
///    bisection stops at 1e-6 of the bounding sphere);
///  - every boundary facet satisfies the facet-distance criterion: its circumcentre is within
///    facet_distance of the surface, so |f(circumcentre)| <= d (plus the bisection slack);
///  - volume: each boundary facet is within d of the surface, so |V_mesh - V| <= A d, with A the
///    meshed surface area (V from implicit_volume(), whose own error is added by the caller).
double check_shape_mesh(const ImplicitShape& shape, const mesh::Mesh& m, const MeshingOptions& o,
    double reference_volume, double reference_tolerance) {
    const auto issues = mesh::check_mesh(m);
    EXPECT_TRUE(issues.empty()) << issues.size() << " issues, first: "
                                << (issues.empty() ? "" : issues.front().message);
    EXPECT_EQ(m.count_components(), 1);
    Index bad_cells = 0;
    for (Index c = 0; c < m.num_cells(); ++c)
        if (m.cells[std::size_t(c)].shape != mesh::CellShape::Tet || !(m.cell_volume(c) > 0))
            ++bad_cells;
    EXPECT_EQ(bad_cells, 0) << "cells that are not tets or have volume <= 0";
    const double R = bounding_radius(shape);
    const double d = o.effective_facet_distance();
    const SurfaceMesh skin = boundary_surface(m);
    double worst_vertex = 0, worst_facet = 0;
    for (const Vec3& x : skin.positions)
        worst_vertex = std::max(worst_vertex, std::abs(implicit_value(shape, x)));
    for (const auto& t : skin.triangles) {
        const Vec3 cc = circumcentre(skin.positions[std::size_t(t[0])],
            skin.positions[std::size_t(t[1])], skin.positions[std::size_t(t[2])]);
        worst_facet = std::max(worst_facet, std::abs(implicit_value(shape, cc)));
    }
    EXPECT_LE(worst_vertex, 1e-5 * R);
    EXPECT_LE(worst_facet, d + 1e-5 * R);
    const double V = m.rest_volume();
    const double A = surface_area(skin);
    EXPECT_NEAR(enclosed_volume(skin), V, 1e-12 * V);
    EXPECT_NEAR(V, reference_volume, A * d + reference_tolerance);
    std::printf("[ shape    ] %d nodes, %d tets, V = %.6e m^3, ref %.6e (rel %+.4f, bound %.4f), "
                "max |f| at vertices %.2e m, at facet circumcentres %.2e m (d = %.1e)\n",
        m.num_nodes(), m.num_cells(), V, reference_volume, V / reference_volume - 1,
        (A * d + reference_tolerance) / reference_volume, worst_vertex, worst_facet, d);
    return V;
}

} // namespace

TEST(ImplicitShape, ValuesAndVolumes) {
    const auto sphere = ImplicitShape::sphere(0.05, Vec3(0.1, 0, 0));
    EXPECT_NEAR(implicit_value(sphere, Vec3(0.1, 0, 0)), -0.05, 1e-15);
    EXPECT_NEAR(implicit_value(sphere, Vec3(0.1, 0.08, 0)), 0.03, 1e-15);
    const auto capsule = ImplicitShape::capsule(0.02, 0.06, Vec3(0, 0, 2));
    EXPECT_NEAR(implicit_value(capsule, Vec3(0, 0, 0.05)), 0, 1e-15);
    EXPECT_NEAR(implicit_value(capsule, Vec3(0.02, 0, 0.01)), 0, 1e-15);
    const auto ellipsoid = ImplicitShape::ellipsoid(Vec3(0.06, 0.04, 0.03));
    EXPECT_NEAR(implicit_value(ellipsoid, Vec3(0, 0.04, 0)), 0, 1e-15);
    const double pi = std::numbers::pi;
    EXPECT_NEAR(implicit_volume(sphere), 4.0 / 3.0 * pi * 1.25e-4, 1e-18);
    EXPECT_NEAR(implicit_volume(capsule), pi * 4e-4 * 0.06 + 4.0 / 3.0 * pi * 8e-6, 1e-18);
    // The octree midpoint rule brackets the analytic volumes within its guaranteed bound.
    for (const auto& shape : { sphere, capsule, ellipsoid }) {
        const VolumeEstimate e = estimate_implicit_volume(shape, 7);
        EXPECT_NEAR(e.volume, implicit_volume(shape), e.error_bound);
        EXPECT_LT(e.error_bound, 0.2 * e.volume);
    }
    // The blob's estimates at two depths agree within their bounds and it is organ-sized.
    const auto blob = ImplicitShape::blob();
    const VolumeEstimate b7 = estimate_implicit_volume(blob, 7),
                         b8 = estimate_implicit_volume(blob, 8);
    EXPECT_NEAR(b7.volume, b8.volume, b7.error_bound + b8.error_bound);
    EXPECT_LT(b8.error_bound, 0.5 * b7.error_bound + 1e-12);
    EXPECT_GT(b8.volume, 1e-4);
    EXPECT_LT(b8.volume, 2e-4);
}

TEST(ImplicitShape, RejectsBadInput) {
    auto bad = ImplicitShape::sphere(-1);
    EXPECT_THROW(mesh_implicit(bad, coarse(0.01)), InputError);
    EXPECT_THROW(mesh_implicit(ImplicitShape::sphere(0.05), coarse(0)), InputError);
    auto nan_axis = ImplicitShape::capsule(0.01, 0.05, Vec3(0, 0, 0));
    EXPECT_THROW(mesh_implicit(nan_axis, coarse(0.01)), InputError);
    MeshingOptions o = coarse(0.01);
    o.facet_angle = 40;
    EXPECT_THROW(mesh_implicit(ImplicitShape::sphere(0.05), o), InputError);
}

// Sphere r = 5 cm at cell size 1 cm (facet distance 1 mm). Every boundary vertex lies on the
// sphere, so the mesh is an inscribed polytope: V_mesh <= V, and since each facet is within
// d = 1 mm of the sphere, V - V_mesh <= A d <= 4 pi r^2 d, i.e. 3 d / r = 6 % of V.
TEST(MeshImplicit, SphereVolumeAndSurface) {
    const double r = 0.05;
    const auto shape = ImplicitShape::sphere(r);
    const MeshingOptions o = coarse(0.01);
    const mesh::Mesh m = mesh_implicit(shape, o);
    const double V = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double Vm = check_shape_mesh(shape, m, o, V, 0);
    EXPECT_LE(Vm, V * (1 + 1e-5)); // inscribed
    EXPECT_GE(Vm, V * (1 - 3 * o.effective_facet_distance() / r)); // 3 d / r
    for (const Vec3& x : m.rest)
        ASSERT_LE(x.norm(), r * (1 + 1e-5));
}

TEST(MeshImplicit, Ellipsoid) {
    const auto shape = ImplicitShape::ellipsoid(Vec3(0.06, 0.04, 0.03), Vec3(0.01, -0.02, 0.03));
    const MeshingOptions o = coarse(0.01);
    const double V = implicit_volume(shape);
    const double Vm = check_shape_mesh(shape, mesh_implicit(shape, o), o, V, 0);
    EXPECT_LE(Vm, V * (1 + 1e-5)); // convex: an inscribed polytope is inside
}

TEST(MeshImplicit, Capsule) {
    const auto shape = ImplicitShape::capsule(0.02, 0.06, Vec3(1, 1, 0));
    const MeshingOptions o = coarse(0.008);
    const double V = implicit_volume(shape);
    const double Vm = check_shape_mesh(shape, mesh_implicit(shape, o), o, V, 0);
    EXPECT_LE(Vm, V * (1 + 1e-5));
}

// The blob has no closed-form volume: compare with the octree midpoint-rule estimate (512^3
// grid), adding its guaranteed error bound (~5 %) to the meshing tolerance A d (~6 % with
// d = 0.5 mm).
TEST(MeshImplicit, Blob) {
    const auto shape = ImplicitShape::blob();
    MeshingOptions o = coarse(0.01);
    o.facet_distance = 0.0005;
    const mesh::Mesh m = mesh_implicit(shape, o);
    const VolumeEstimate e = estimate_implicit_volume(shape, 9);
    std::printf("[ blob     ] volume estimate %.6e +- %.2e m^3\n", e.volume, e.error_bound);
    check_shape_mesh(shape, m, o, e.volume, e.error_bound);
    // Organ-sized: about 10 cm across.
    Vec3 lo = m.rest[0], hi = m.rest[0];
    for (const Vec3& x : m.rest) {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    EXPECT_GT(hi.x() - lo.x(), 0.09);
    EXPECT_LT(hi.x() - lo.x(), 0.12);
}

TEST(MeshImplicit, DeterministicForAFixedSeed) {
    const auto shape = ImplicitShape::blob();
    MeshingOptions o = coarse(0.012);
    o.seed = 7;
    const mesh::Mesh a = mesh_implicit(shape, o);
    const mesh::Mesh b = mesh_implicit(shape, o);
    ASSERT_EQ(a.num_nodes(), b.num_nodes());
    ASSERT_EQ(a.num_cells(), b.num_cells());
    for (Index n = 0; n < std::min<Index>(a.num_nodes(), 20); ++n)
        EXPECT_EQ(a.rest[std::size_t(n)], b.rest[std::size_t(n)]) << "node " << n;
    for (Index c = 0; c < std::min<Index>(a.num_cells(), 20); ++c)
        EXPECT_EQ(a.cells[std::size_t(c)].nodes, b.cells[std::size_t(c)].nodes) << "cell " << c;
    EXPECT_EQ(a.rest_volume(), b.rest_volume());
}

// The default optimisers (perturb, exude) on the organ-like blob: no slivers where the plain
// refined mesh has some, a larger smallest dihedral angle, and the volume still within A d.
TEST(MeshImplicit, DefaultOptimisersRemoveSlivers) {
    const auto shape = ImplicitShape::blob();
    MeshingOptions o;
    o.cell_size = 0.008;
    const mesh::Mesh optimised = mesh_implicit(shape, o);
    const mesh::Mesh plain = mesh_implicit(shape, coarse(0.008));
    const TetQuality q = tet_quality(optimised), p = tet_quality(plain);
    std::printf("[ blob     ] plain: %s\n[ blob     ] perturb+exude: %s\n", to_string(p).c_str(),
        to_string(q).c_str());
    EXPECT_TRUE(mesh::check_mesh(optimised).empty());
    EXPECT_GT(q.min_dihedral_deg, p.min_dihedral_deg);
    EXPECT_FALSE(q.has_slivers()) << to_string(q);
    EXPECT_GE(q.radius_ratio_p1, p.radius_ratio_p1);
    const double A = surface_area(boundary_surface(optimised));
    EXPECT_NEAR(optimised.rest_volume(), plain.rest_volume(), A * o.effective_facet_distance());
}

TEST(MeshImplicit, OptimizedMeshIsValid) {
    const auto shape = ImplicitShape::sphere(0.05);
    MeshingOptions o = coarse(0.015);
    o.odt = true;
    o.perturb = true;
    o.exude = true;
    const mesh::Mesh m = mesh_implicit(shape, o);
    EXPECT_TRUE(mesh::check_mesh(m).empty());
    const double V = implicit_volume(shape);
    EXPECT_NEAR(m.rest_volume(), V, 3 * o.effective_facet_distance() / 0.05 * V);
}
