// Convex hull of a point set as one polyhedral cell. CGAL's convex_hull_3 triangulates the hull;
// triangles across an edge whose fourth point is coplanar (CGAL::coplanar, exact on the double
// input since the hull uses no constructed points) are merged into one face, whose boundary is
// then walked into a loop. The hull's surface mesh is oriented outward, so the loops are too.
// Decimal input rounded to doubles is rarely exactly coplanar off the coordinate planes (a
// rotated cube), so points within kFlatTol x (bounding-box diagonal) of a plane or a line count
// as on it; that is 10x tighter than the planarity check of mesh validation (1e-9).
#include "polycut/meshing/convex_hull.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace polycut::meshing {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using HullMesh = CGAL::Surface_mesh<Point>;
constexpr double kFlatTol = 1e-10;

Vec3 vec(const Point& p) {
    return { p.x(), p.y(), p.z() };
}

/// Exactly coplanar, or d within tol of the plane through a, b, c.
bool coplanar(const Point& a, const Point& b, const Point& c, const Point& d, double tol) {
    if (CGAL::coplanar(a, b, c, d))
        return true;
    const Vec3 n = (vec(b) - vec(a)).cross(vec(c) - vec(a));
    return std::abs(n.dot(vec(d) - vec(a))) <= tol * n.norm();
}

/// Exactly collinear, or b within tol of the line through a and c.
bool collinear(const Point& a, const Point& b, const Point& c, double tol) {
    if (CGAL::collinear(a, b, c))
        return true;
    const Vec3 ac = vec(c) - vec(a);
    return (vec(b) - vec(a)).cross(ac).norm() <= tol * ac.norm();
}

std::string point_text(const Vec3& p) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", p.x(), p.y(), p.z());
    return buf;
}

/// Union-find over the hull's triangles.
struct Groups {
    std::vector<std::size_t> parent;
    explicit Groups(std::size_t n)
        : parent(n) {
        std::iota(parent.begin(), parent.end(), std::size_t(0));
    }
    std::size_t find(std::size_t i) {
        while (parent[i] != i)
            i = parent[i] = parent[parent[i]];
        return i;
    }
    void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

/// Throws unless the set spans 3D: exactly (a pair, a non-collinear third and a non-coplanar
/// fourth) and by more than tol (distance of the farthest point from the least-squares plane).
void check_volume(const std::vector<Point>& p, const std::vector<Vec3>& x, double tol) {
    std::size_t i1 = 1;
    while (i1 < p.size() && p[i1] == p[0])
        ++i1;
    std::size_t i2 = i1 + 1;
    while (i2 < p.size() && CGAL::collinear(p[0], p[i1], p[i2]))
        ++i2;
    std::size_t i3 = i2 + 1;
    while (i3 < p.size() && CGAL::coplanar(p[0], p[i1], p[i2], p[i3]))
        ++i3;
    bool flat = i3 >= p.size();
    if (!flat) {
        Vec3 mean = Vec3::Zero();
        for (const Vec3& xi : x)
            mean += xi;
        mean /= double(x.size());
        Mat3 scatter = Mat3::Zero();
        for (const Vec3& xi : x)
            scatter += (xi - mean) * (xi - mean).transpose();
        const Vec3 normal = Eigen::SelfAdjointEigenSolver<Mat3>(scatter).eigenvectors().col(0);
        double width = 0;
        for (const Vec3& xi : x)
            width = std::max(width, std::abs(normal.dot(xi - mean)));
        flat = width <= tol;
    }
    if (flat)
        throw ConvexHullError(kNone,
            "all " + std::to_string(p.size())
                + " points lie on one plane (or line): their hull has no volume");
}
} // namespace

ConvexHullError::ConvexHullError(Index index, const std::string& what)
    : InputError(index == kNone ? "points" : "points/" + std::to_string(index), what)
    , m_index(index) { }

ConvexPolyhedron convex_hull(const std::vector<Vec3>& points) {
    const std::size_t n = points.size();
    if (n < 4)
        throw ConvexHullError(
            kNone, "needs at least 4 points (a tetrahedron), got " + std::to_string(n));
    std::vector<Point> p;
    p.reserve(n);
    std::map<Point, Index> index_of;
    for (std::size_t i = 0; i < n; ++i) {
        if (!points[i].allFinite())
            throw ConvexHullError(Index(i), "has a non-finite coordinate");
        p.emplace_back(points[i].x(), points[i].y(), points[i].z());
        const auto [it, inserted] = index_of.emplace(p.back(), Index(i));
        if (!inserted)
            throw ConvexHullError(Index(i),
                "repeats point " + std::to_string(it->second) + " " + point_text(points[i]));
    }
    Eigen::AlignedBox<double, 3> box;
    for (const Vec3& x : points)
        box.extend(x);
    const double tol = kFlatTol * box.diagonal().norm();
    check_volume(p, points, tol);

    HullMesh hull;
    CGAL::convex_hull_3(p.begin(), p.end(), hull);

    // Merge the triangles of each facet plane: neighbours across an edge are coplanar when the
    // far corner of one lies on the other's plane.
    Groups groups(hull.number_of_faces());
    for (const auto f : hull.faces()) {
        const auto h0 = hull.halfedge(f);
        const Point& a = hull.point(hull.source(h0));
        const Point& b = hull.point(hull.target(h0));
        const Point& c = hull.point(hull.target(hull.next(h0)));
        for (const auto h : hull.halfedges_around_face(h0)) {
            const auto g = hull.face(hull.opposite(h));
            if (g == HullMesh::null_face() || std::size_t(g) < std::size_t(f))
                continue;
            const Point& far = hull.point(hull.target(hull.next(hull.opposite(h))));
            if (coplanar(a, b, c, far, tol))
                groups.unite(std::size_t(f), std::size_t(g));
        }
    }

    // Boundary halfedges of each group, keyed by source vertex (a convex polygon visits each
    // corner once), then walked head to tail.
    std::map<std::size_t, std::map<std::size_t, HullMesh::Halfedge_index>> boundary;
    for (const auto h : hull.halfedges()) {
        const auto f = hull.face(h);
        const auto g = hull.face(hull.opposite(h));
        if (f == HullMesh::null_face())
            continue;
        const std::size_t group = groups.find(std::size_t(f));
        if (g != HullMesh::null_face() && groups.find(std::size_t(g)) == group)
            continue;
        boundary[group][std::size_t(hull.source(h))] = h;
    }

    ConvexPolyhedron out;
    out.nodes = points;
    std::vector<int> faces_of(n, 0);
    for (const auto& [group, edges] : boundary) {
        std::vector<Index> loop;
        auto h = edges.begin()->second;
        for (std::size_t k = 0; k <= edges.size(); ++k) {
            loop.push_back(index_of.at(hull.point(hull.source(h))));
            const auto next = edges.find(std::size_t(hull.target(h)));
            if (next == edges.end())
                throw ConvexHullError(kNone, "internal error: a hull facet's boundary is open");
            h = next->second;
            if (h == edges.begin()->second)
                break;
        }
        if (loop.size() != edges.size())
            throw ConvexHullError(kNone, "internal error: a hull facet's boundary is not one loop");
        // A node on a straight stretch of the loop lies on an edge of the hull: not a corner.
        const std::size_t m = loop.size();
        for (std::size_t k = 0; k < m; ++k) {
            const Index prev = loop[(k + m - 1) % m], mid = loop[k], next = loop[(k + 1) % m];
            if (collinear(p[std::size_t(prev)], p[std::size_t(mid)], p[std::size_t(next)], tol))
                throw ConvexHullError(mid,
                    point_text(points[std::size_t(mid)])
                        + " lies on an edge of the convex hull (between points "
                        + std::to_string(prev) + " and " + std::to_string(next)
                        + "), not at a corner: every node of a polyhedral cell must be a corner");
        }
        for (Index v : loop)
            ++faces_of[std::size_t(v)];
        out.faces.push_back(std::move(loop));
    }
    for (std::size_t i = 0; i < n; ++i)
        if (faces_of[i] == 0)
            throw ConvexHullError(Index(i),
                point_text(points[i])
                    + " is not a corner of the convex hull (it lies inside it, inside one of its "
                      "faces or on an edge): every node of a polyhedral cell must be a corner");
    // convex_hull_3 orders its faces by memory addresses, which depend on what ran before:
    // start each loop at its smallest id and sort the loops, so that the same points always give
    // the same faces (and bit-identical volumes and bases).
    for (std::vector<Index>& loop : out.faces)
        std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    std::sort(out.faces.begin(), out.faces.end());
    return out;
}

mesh::Mesh convex_hull_cell(const std::vector<Vec3>& points) {
    ConvexPolyhedron hull = convex_hull(points);
    return mesh::Mesh::from_polyhedra(std::move(hull.nodes), { hull.faces });
}

std::vector<Vec3> truncated_octahedron_points(double edge, const Vec3& center) {
    if (!(edge > 0) || !std::isfinite(edge))
        throw InputError("edge", "must be a finite length > 0 [m]");
    const double s = edge / std::sqrt(2.0);
    constexpr int kPerm[6][3]
        = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
    std::vector<Vec3> out;
    out.reserve(24);
    for (const auto& perm : kPerm)
        for (int s1 : { -1, 1 })
            for (int s2 : { -1, 1 }) {
                Vec3 v = Vec3::Zero();
                v[perm[1]] = s1 * 1.0;
                v[perm[2]] = s2 * 2.0;
                out.push_back(center + s * v);
            }
    return out;
}

} // namespace polycut::meshing
