// Signed distances of the contact shapes against closed forms, the triangle mesh (CGAL AABB
// tree) against the box it tessellates, and the penalty force and its implicit stiffness
// against the analytic force and a central finite difference.
#include "polycut/contact/contact_field.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace polycut;
using namespace polycut::contact;

namespace {
Pose rotated(const Vec3& position) {
    Pose p;
    p.position = position;
    p.rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized());
    return p;
}

/// The closed, outward-oriented 12-triangle surface of the box [-h, h].
std::shared_ptr<const TriangleMeshDistance> box_mesh(const Vec3& h) {
    std::vector<Vec3> v;
    for (int i = 0; i < 8; ++i)
        v.emplace_back(
            (i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
    const std::vector<std::array<Index, 3>> t
        = { { 0, 2, 1 }, { 1, 2, 3 }, { 4, 5, 6 }, { 5, 7, 6 }, { 0, 1, 4 }, { 1, 5, 4 },
              { 2, 6, 3 }, { 3, 6, 7 }, { 0, 4, 2 }, { 2, 4, 6 }, { 1, 3, 5 }, { 3, 7, 5 } };
    return std::make_shared<TriangleMeshDistance>(v, t);
}

Shape make(Shape::Kind kind) {
    Shape s;
    s.kind = kind;
    s.half_extents = Vec3(0.02, 0.03, 0.01);
    s.radius = 0.01;
    s.half_length = 0.02;
    if (kind == Shape::Kind::TriangleMesh)
        s.mesh = box_mesh(s.half_extents);
    return s;
}

/// One sample of area `area` at node 0 of a one-node state at p.
struct OnePoint {
    ContactField field;
    MatX3 x = MatX3::Zero(1, 3), v = MatX3::Zero(1, 3);
    explicit OnePoint(double area) {
        Samples s;
        s.nodes = { 0 };
        s.weights = { 1.0 };
        s.areas = { area };
        s.offsets = { 0, 1 };
        field.set_samples(s);
    }
    Vec3 force_at(const Vec3& p) {
        x.row(0) = p.transpose();
        integrate::PenaltySet set;
        field.evaluate(x, v, 0.0, set);
        return set.points.empty() ? Vec3::Zero() : set.points[0].force;
    }
};
} // namespace

TEST(Shapes, SignedDistancesMatchClosedForms) {
    const Pose pose = rotated(Vec3(0.1, -0.2, 0.3));
    const double tol = 1e-14;
    // Sphere: |p - c| - r along a direction.
    const Vec3 dir = Vec3(1, -2, 0.5).normalized();
    for (const double r : { 0.003, 0.01, 0.025 }) {
        const SignedDistance d
            = signed_distance(make(Shape::Kind::Sphere), pose, pose.position + r * dir);
        EXPECT_NEAR(d.phi, r - 0.01, tol);
        EXPECT_NEAR((d.normal - dir).norm(), 0, 1e-12);
    }
    // Plane: the local z coordinate.
    const Vec3 up = pose.rotation * Vec3::UnitZ();
    const SignedDistance dp
        = signed_distance(make(Shape::Kind::Plane), pose, pose.position - 0.004 * up);
    EXPECT_NEAR(dp.phi, -0.004, tol);
    EXPECT_NEAR((dp.normal - up).norm(), 0, 1e-12);
    // Box: inside, nearest face (local z, half extent 0.01, point at z = 0.007: phi = -0.003);
    // outside past a corner, the distance to the corner.
    const Shape box = make(Shape::Kind::Box);
    EXPECT_NEAR(
        signed_distance(box, pose, pose.to_world(Vec3(0.001, 0.002, 0.007))).phi, -0.003, tol);
    const Vec3 corner(0.02, 0.03, 0.01), off(0.001, 0.002, 0.002);
    EXPECT_NEAR(signed_distance(box, pose, pose.to_world(corner + off)).phi, off.norm(), tol);
    // Capsule: distance to the axis segment minus the radius, at the side and past an end.
    const Shape cap = make(Shape::Kind::Capsule);
    EXPECT_NEAR(
        signed_distance(cap, pose, pose.to_world(Vec3(0.004, 0.003, 0.015))).phi, -0.005, tol);
    EXPECT_NEAR(signed_distance(cap, pose, pose.to_world(Vec3(0, 0, 0.035))).phi, 0.005, tol);
}

TEST(Shapes, TriangleMeshDistanceEqualsTheBoxItTessellates) {
    // The CGAL AABB-tree distance of a box's 12 triangles agrees with the box's exact signed
    // distance (and normal where it is unique) at 2,000 points inside and around it.
    const Pose pose = rotated(Vec3(0.05, 0.0, -0.02));
    const Shape box = make(Shape::Kind::Box), mesh = make(Shape::Kind::TriangleMesh);
    std::srand(7);
    auto uniform = [] { return 2.0 * std::rand() / RAND_MAX - 1.0; };
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 local(0.03 * uniform(), 0.04 * uniform(), 0.02 * uniform());
        const Vec3 p = pose.to_world(local);
        const SignedDistance a = signed_distance(box, pose, p), b = signed_distance(mesh, pose, p);
        worst = std::max(worst, std::abs(a.phi - b.phi));
        if (a.phi < -1e-4) // inside, away from the medial surface ties
            continue;
        EXPECT_NEAR((a.normal - b.normal).norm(), 0, 1e-9) << i;
    }
    EXPECT_LT(worst, 1e-12);
    EXPECT_NEAR(mesh.mesh->volume(), volume(box), 1e-15);
}

TEST(Penalty, ForceIsStiffnessTimesAreaTimesDepthAlongTheNormal) {
    // f = -k a phi n: 1e6 N/m^3 x 1e-4 m^2 x 2 mm = 0.2 N out of the plane; none outside.
    OnePoint one(1e-4);
    Body floor;
    floor.shape = make(Shape::Kind::Plane);
    floor.params.stiffness = 1e6;
    one.field.add_body(floor);
    const Vec3 f = one.force_at(Vec3(0.3, -0.1, -0.002));
    EXPECT_NEAR((f - Vec3(0, 0, 0.2)).norm(), 0, 1e-14);
    EXPECT_EQ(one.force_at(Vec3(0, 0, 1e-9)), Vec3::Zero());
    // Energy 1/2 k a phi^2.
    EXPECT_NEAR(one.field.energy(one.x), 0.0, 0); // the last point was outside
    one.force_at(Vec3(0, 0, -0.002));
    EXPECT_NEAR(one.field.energy(one.x), 0.5 * 1e6 * 1e-4 * 4e-6, 1e-18);
}

TEST(Penalty, ImplicitStiffnessMatchesAFiniteDifference) {
    // -df/dp by central differences (step 1e-7 m) against the block the system gets, K = k a
    // n n^T. Flat contacts (plane, box face, the mesh's face) have no curvature: equal to
    // 1e-6 relative. Curved ones (sphere, capsule) differ only by the dropped curvature term
    // k a phi / rho (I - n n^T), rho the distance to the centre (axis): checked as such.
    const Pose pose = rotated(Vec3(0.01, 0.02, 0.03));
    const double k = 3e6, area = 2e-5, h = 1e-7;
    struct Case {
        Shape::Kind kind;
        Vec3 local; ///< a point inside, away from edges
        double rho; ///< 0 flat; else the distance to the centre or the axis
    };
    const Case cases[] = { { Shape::Kind::Plane, Vec3(0.01, 0.0, -0.003), 0 },
        { Shape::Kind::Box, Vec3(0.003, 0.004, 0.008), 0 },
        { Shape::Kind::TriangleMesh, Vec3(0.003, 0.004, 0.008), 0 },
        { Shape::Kind::Sphere, Vec3(0.004, 0.003, 0.006), Vec3(0.004, 0.003, 0.006).norm() },
        { Shape::Kind::Capsule, Vec3(0.005, 0.004, 0.01), Vec3(0.005, 0.004, 0).norm() } };
    for (const Case& c : cases) {
        OnePoint one(area);
        Body b;
        b.shape = make(c.kind);
        b.pose = pose;
        b.params.stiffness = k;
        one.field.add_body(b);
        const Vec3 p = pose.to_world(c.local);
        one.x.row(0) = p.transpose();
        integrate::PenaltySet set;
        one.field.evaluate(one.x, one.v, 0.0, set);
        ASSERT_EQ(set.points.size(), 1u);
        const Mat3 K = set.points[0].stiffness;
        Mat3 fd;
        for (int j = 0; j < 3; ++j) {
            const Vec3 e = h * Vec3::Unit(j);
            fd.col(j) = -(one.force_at(p + e) - one.force_at(p - e)) / (2 * h);
        }
        const SignedDistance d = signed_distance(b.shape, pose, p);
        Mat3 expected = K;
        if (c.rho > 0) {
            // the axis direction of a capsule carries no curvature
            Mat3 tangent = Mat3::Identity() - d.normal * d.normal.transpose();
            if (c.kind == Shape::Kind::Capsule) {
                const Vec3 axis = pose.rotation * Vec3::UnitZ();
                tangent -= axis * axis.transpose();
            }
            expected += k * area * d.phi / c.rho * tangent;
        }
        EXPECT_LT((fd - expected).norm(), 1e-6 * K.norm()) << int(c.kind) << "\n" << fd;
        EXPECT_NEAR(K.norm(), k * area, 1e-9 * k * area); // n n^T has norm 1
    }
}

TEST(Penalty, FrictionOpposesSlidingAndIsBoundedByCoulomb) {
    // A sample pressed 1 mm into a plane, sliding at 0.1 m/s along x over a body moving at
    // 0.02 m/s: the friction force is mu |f_n| against the relative velocity (beyond the slip
    // velocity), and the body's reaction is its opposite.
    OnePoint one(1e-4);
    Body floor;
    floor.shape = make(Shape::Kind::Plane);
    floor.params.stiffness = 1e6;
    floor.params.friction = 0.4;
    floor.velocity = Vec3(0.02, 0, 0);
    const long id = one.field.add_body(floor);
    one.x.row(0) = Vec3(0, 0, -0.001).transpose();
    one.v.row(0) = Vec3(0.1, 0, 0).transpose();
    integrate::PenaltySet set;
    one.field.evaluate(one.x, one.v, 0.0, set);
    ASSERT_EQ(set.points.size(), 1u);
    const integrate::PenaltyPoint& pt = set.points[0];
    const Vec3 friction = -pt.damping * (one.v.row(0).transpose() - pt.other_velocity);
    const double fn = 1e6 * 1e-4 * 0.001;
    EXPECT_NEAR((friction - Vec3(-0.4 * fn, 0, 0)).norm(), 0, 1e-15);
    const Reaction r = one.field.reactions(one.x, one.v).at(id);
    EXPECT_NEAR((r.force - Vec3(0.4 * fn, 0, -fn)).norm(), 0, 1e-15);
    EXPECT_EQ(r.points, 1);
    EXPECT_NEAR(r.max_depth, 0.001, 1e-15);
}
