// 2D harmonic coordinates of a planar polygon by the method of fundamental solutions (seed 001
// eq. 11-14 with psi(r) = log r): they are the Dirichlet data of the 3D harmonic basis on each
// face, and are themselves fitted to piecewise linear data on the edges.
#include "harmonic_detail.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <cmath>
#include <limits>

namespace polycut::basis::detail {

bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const Vec2& a = poly[i];
        const Vec2& b = poly[j];
        if ((a.y() > p.y()) != (b.y() > p.y())
            && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
            in = !in;
    }
    return in;
}

double distance_to_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec2& a = poly[i];
        const Vec2& b = poly[(i + 1) % poly.size()];
        const Vec2 ab = b - a;
        const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
        best = std::min(best, (a + t * ab - p).norm());
    }
    return best;
}

std::vector<Vec2> polygon_grid(const std::vector<Vec2>& poly, double h, double margin) {
    Vec2 lo = poly[0], hi = poly[0];
    for (const auto& p : poly) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    std::vector<Vec2> out;
    // grid centred on the box so that symmetric polygons get symmetric samples
    const Vec2 mid = 0.5 * (lo + hi);
    const int nx = int(std::floor(0.5 * (hi.x() - lo.x()) / h));
    const int ny = int(std::floor(0.5 * (hi.y() - lo.y()) / h));
    for (int i = -nx; i <= nx; ++i)
        for (int j = -ny; j <= ny; ++j) {
            const Vec2 p = mid + h * Vec2(i, j);
            if (inside_polygon(poly, p) && distance_to_polygon(poly, p) >= margin)
                out.push_back(p);
        }
    return out;
}

HarmonicFace::HarmonicFace(const std::vector<Vec3>& loop, const HarmonicOptions& options) {
    const std::size_t k = loop.size();
    m_normal = geometry::polygon_normal(loop);
    m_origin = geometry::polygon_centroid(loop);
    geometry::Aabb box;
    for (const auto& p : loop)
        box.extend(p);
    m_scale = box.diagonal();
    m_e1 = (loop[1] - loop[0]).normalized();
    m_e1 = (m_e1 - m_e1.dot(m_normal) * m_normal).normalized();
    m_e2 = m_normal.cross(m_e1);
    for (const auto& p : loop)
        m_poly.push_back(to_2d(p));

    // 001 eq. 12: kernels at boundary samples (vertices and edge_samples per edge) moved
    // outward by xi * size along the interpolated outward normal; a centre that lands inside
    // or too close to the polygon (non-convex faces) is moved less, or dropped.
    const int ne = std::max(0, options.edge_samples);
    const double xi = options.offset; // the scaled face size is 1
    std::vector<Vec2> edge_normal(k);
    for (std::size_t i = 0; i < k; ++i) {
        const Vec2 t = (m_poly[(i + 1) % k] - m_poly[i]).normalized();
        edge_normal[i] = Vec2(t.y(), -t.x());
    }
    double perimeter = 0;
    for (std::size_t i = 0; i < k; ++i)
        perimeter += (m_poly[(i + 1) % k] - m_poly[i]).norm();
    const double min_spacing = 0.3 * perimeter / double(k * std::size_t(ne + 1));
    auto place = [&](const Vec2& s, const Vec2& n) {
        for (double f : { 1.0, 0.5, 0.25 }) {
            const Vec2 c = s + f * xi * n;
            if (!inside_polygon(m_poly, c) && distance_to_polygon(m_poly, c) >= 0.5 * f * xi) {
                for (const auto& other : m_kernel)
                    if ((other - c).norm() < min_spacing)
                        return; // near-duplicate kernel (short edges): drop it
                m_kernel.push_back(c);
                return;
            }
        }
    };
    for (std::size_t i = 0; i < k; ++i) {
        const Vec2 nv = (edge_normal[(i + k - 1) % k] + edge_normal[i]).normalized();
        place(m_poly[i], nv);
        for (int j = 1; j <= ne; ++j) {
            const double t = double(j) / (ne + 1);
            place((1 - t) * m_poly[i] + t * m_poly[(i + 1) % k], edge_normal[i]);
        }
    }
    // 001 eq. 13: collocation at about ratio x the kernel density: vertices (Kronecker data)
    // and points inside the edges (linear data).
    const Index n = Index(m_kernel.size());
    const int mc = std::max(1, int(std::lround(options.collocation_ratio * (ne + 1))) - 1);
    const Index m = Index(k * std::size_t(mc + 1));
    MatX A(m, n + 3);
    MatX B = MatX::Zero(m, Index(k));
    Index row = 0;
    auto add_row = [&](const Vec2& c) {
        for (Index j = 0; j < n; ++j)
            A(row, j) = std::log((c - m_kernel[std::size_t(j)]).norm());
        A(row, n) = c.x();
        A(row, n + 1) = c.y();
        A(row, n + 2) = 1.0;
    };
    for (std::size_t i = 0; i < k; ++i) {
        add_row(m_poly[i]);
        B(row++, Index(i)) = 1.0;
        for (int j = 1; j <= mc; ++j) {
            const double t = double(j) / (mc + 1);
            add_row((1 - t) * m_poly[i] + t * m_poly[(i + 1) % k]);
            B(row, Index(i)) = 1 - t;
            B(row++, Index((i + 1) % k)) = t;
        }
    }
    MatX X(Index(k), 3);
    for (std::size_t i = 0; i < k; ++i)
        X.row(Index(i)) << m_poly[i].x(), m_poly[i].y(), 1.0;
    m_coef = solve_mfs(std::move(A), B, X, n, options.solver);
}

Vec2 HarmonicFace::to_2d(const Vec3& x) const {
    const Vec3 d = (x - m_origin) / m_scale;
    return { d.dot(m_e1), d.dot(m_e2) };
}

Vec3 HarmonicFace::to_3d(const Vec2& q) const {
    return m_origin + m_scale * (q.x() * m_e1 + q.y() * m_e2);
}

void HarmonicFace::evaluate(const Vec3& x, Eigen::Ref<VecX> out) const {
    const Vec2 q = to_2d(x);
    const Index n = Index(m_kernel.size());
    VecX psi(n + 3);
    for (Index j = 0; j < n; ++j)
        psi[j] = std::log((q - m_kernel[std::size_t(j)]).norm());
    psi[n] = q.x();
    psi[n + 1] = q.y();
    psi[n + 2] = 1.0;
    out.noalias() = m_coef.transpose() * psi;
}

} // namespace polycut::basis::detail
