// Chin-Lasserre-Sukumar recursion (polyhedron_moments.hpp). For f homogeneous of degree q and a
// d-dimensional polytope P with facets F_i on the planes a_i . x = b_i (a_i unit outward):
//   int_P f = 1/(d + q) [ sum_i b_i int_{F_i} f + int_P x0 . grad f ],
// any point x0 (here 0 for the volume, a vertex for a face, the first end point for an edge), and
// the same one dimension lower with b_i the signed distance from x0 to the facet's plane within P.
// Applied to all monomials of degree <= D at once, lowest degree first, the grad f term reuses
// the integrals of degree q - 1 already computed.
#include "polycut/dg/polyhedron_moments.hpp"

#include "polycut/common/error.hpp"
#include "polycut/dg/polynomial.hpp"

#include <string>

namespace polycut::dg {
namespace {
void check(int degree, double scale) {
    if (degree < 0 || degree > kMaxDegree)
        throw InputError("degree",
            "moment degree " + std::to_string(degree) + " outside [0, " + std::to_string(kMaxDegree)
                + "]");
    if (!(scale > 0) || !std::isfinite(scale))
        throw InputError("scale", "the local scale must be positive and finite");
}

/// Adds to out[k] (for each monomial k) the term x0 . grad m_k integrated, from the integrals of
/// lower degree in `integral` (filled for degrees < the current one), and divides by (dim + q).
/// Processes degree q only: entries [begin, end).
void close_degree(VecX& integral, const Vec3& x0, int dim, int q, int begin, int end) {
    for (int k = begin; k < end; ++k) {
        const auto& e = exponent(k);
        double grad = 0;
        if (e[0] > 0)
            grad += x0[0] * e[0] * integral[monomial_index(e[0] - 1, e[1], e[2])];
        if (e[1] > 0)
            grad += x0[1] * e[1] * integral[monomial_index(e[0], e[1] - 1, e[2])];
        if (e[2] > 0)
            grad += x0[2] * e[2] * integral[monomial_index(e[0], e[1], e[2] - 1)];
        integral[k] = (integral[k] + grad) / double(dim + q);
    }
}

/// Edge integrals (unit: xi-length) of all monomials of degree <= degree over [p, r].
VecX segment_moments(const Vec3& p, const Vec3& r, int degree) {
    const int n = num_monomials(degree);
    VecX out = VecX::Zero(n);
    const double length = (r - p).norm();
    const VecX at_r = monomial_values(degree, r);
    // x0 = p: the end point p is at distance 0, r at distance `length`.
    for (int q = 0; q <= degree; ++q) {
        const int begin = num_monomials(q - 1), end = num_monomials(q);
        for (int k = begin; k < end; ++k)
            out[k] = length * at_r[k];
        close_degree(out, p, 1, q, begin, end);
    }
    return out;
}

/// Face integrals in xi units of a polygon given by its local points (in order) and unit normal.
VecX local_polygon_moments(const std::vector<Vec3>& xi, const Vec3& normal, int degree) {
    const int n = num_monomials(degree);
    const std::size_t m = xi.size();
    const Vec3& x0 = xi[0];
    // Edge terms: the signed in-plane distance from x0 to each edge's line times its integrals.
    std::vector<double> distance(m);
    std::vector<VecX> edges(m);
    for (std::size_t i = 0; i < m; ++i) {
        const Vec3& a = xi[i];
        const Vec3& b = xi[(i + 1) % m];
        const Vec3 t = b - a;
        const double len = t.norm();
        distance[i] = 0;
        if (len == 0 || i == 0 || i + 1 == m)
            continue; // the two edges through x0 are at distance 0
        const Vec3 outward = (t / len).cross(normal);
        distance[i] = (a - x0).dot(outward);
        edges[i] = segment_moments(a, b, degree);
    }
    VecX out = VecX::Zero(n);
    for (int q = 0; q <= degree; ++q) {
        const int begin = num_monomials(q - 1), end = num_monomials(q);
        for (std::size_t i = 0; i < m; ++i)
            if (distance[i] != 0)
                out.segment(begin, end - begin)
                    += distance[i] * edges[i].segment(begin, end - begin);
        close_degree(out, x0, 2, q, begin, end);
    }
    return out;
}

std::vector<Vec3> to_local(const std::vector<Vec3>& points, std::span<const Index> loop,
    const Vec3& origin, double scale) {
    std::vector<Vec3> xi;
    xi.reserve(loop.size());
    for (Index v : loop)
        xi.push_back((points[std::size_t(v)] - origin) / scale);
    return xi;
}
} // namespace

bool is_planar(const std::vector<Vec3>& points, std::span<const Index> loop) {
    if (loop.size() <= 3)
        return true;
    Vec3 mean = Vec3::Zero();
    for (Index v : loop)
        mean += points[std::size_t(v)] / double(loop.size());
    double size = 0;
    for (Index v : loop)
        size = std::max(size, (points[std::size_t(v)] - mean).norm());
    const Vec3 n = polygon_normal(points, loop, nullptr);
    for (Index v : loop)
        if (std::abs((points[std::size_t(v)] - mean).dot(n)) > kPlanarTolerance * size)
            return false;
    return true;
}

Vec3 polygon_normal(const std::vector<Vec3>& points, std::span<const Index> loop, double* area) {
    Vec3 n = Vec3::Zero();
    const Vec3& base = points[std::size_t(loop[0])];
    for (std::size_t i = 1; i + 1 < loop.size(); ++i)
        n += (points[std::size_t(loop[i])] - base).cross(points[std::size_t(loop[i + 1])] - base);
    const double twice = n.norm();
    if (area)
        *area = 0.5 * twice;
    return twice > 0 ? Vec3(n / twice) : Vec3::Zero();
}

VecX polygon_moments(const std::vector<Vec3>& points, std::span<const Index> loop,
    const Vec3& origin, double scale, int degree) {
    check(degree, scale);
    const Vec3 normal = polygon_normal(points, loop, nullptr);
    if (loop.size() < 3 || normal.isZero())
        return VecX::Zero(num_monomials(degree));
    return local_polygon_moments(to_local(points, loop, origin, scale), normal, degree)
        * (scale * scale);
}

VecX polyhedron_moments(const std::vector<Vec3>& points,
    const std::vector<std::vector<Index>>& loops, const Vec3& origin, double scale, int degree) {
    check(degree, scale);
    const int n = num_monomials(degree);
    VecX out = VecX::Zero(n);
    // One planar piece: b = distance of its plane from the local origin (x0 = 0 for the
    // volume).
    auto add_piece = [&](const std::vector<Vec3>& xi) {
        Vec3 twice = Vec3::Zero();
        for (std::size_t i = 1; i + 1 < xi.size(); ++i)
            twice += (xi[i] - xi[0]).cross(xi[i + 1] - xi[0]);
        if (!(twice.norm() > 0))
            return;
        const Vec3 normal = twice.normalized();
        Vec3 mean = Vec3::Zero();
        for (const Vec3& x : xi)
            mean += x;
        const double b = normal.dot(mean / double(xi.size()));
        if (b != 0)
            out += b * local_polygon_moments(xi, normal, degree);
    };
    for (const auto& loop : loops) {
        if (loop.size() < 3)
            continue;
        const std::vector<Vec3> xi = to_local(points, loop, origin, scale);
        if (is_planar(points, loop)) {
            add_piece(xi);
            continue;
        }
        // A warped face: the triangles around its mean point (face_integral_parts does the
        // same, so neighbours and face terms agree on the surface).
        Vec3 mean = Vec3::Zero();
        for (const Vec3& x : xi)
            mean += x / double(xi.size());
        for (std::size_t i = 0; i < xi.size(); ++i)
            add_piece({ mean, xi[i], xi[(i + 1) % xi.size()] });
    }
    for (int q = 0; q <= degree; ++q) {
        const int begin = num_monomials(q - 1), end = num_monomials(q);
        for (int k = begin; k < end; ++k)
            out[k] /= double(3 + q);
    }
    return out * (scale * scale * scale);
}

} // namespace polycut::dg
