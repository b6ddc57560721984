// Evaluation of 3D mean value coordinates and their analytic gradients (seed 000 sec. 3.2,
// Appendix A). The weights are computed per surface triangle as in Ju, Schaefer & Warren 2005:
// the mean vector of the spherical triangle, m_T = 1/2 sum_e theta_e n_e, is written as
// m_T = sum_v w_v d_v (d_v = x_v - x) by Cramer's rule, w_v = m_T . (d_a x d_b) / det[d_0 d_1 d_2]
// with (a, b) the edge opposite v. Summed over triangles this equals 000 eq. 7-8 (the edge terms
// of eq. 7 regroup the same quantities per one-ring); normalized as 000 eq. 9. The gradient
// differentiates this expression analytically (the role of 000 eq. 19-22).
#include "polycut/basis/mean_value.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace polycut::basis {
namespace {
// The interior formula stays accurate for values very close to a face (the near-singular
// determinant scales all weights of the dominant triangle alike), so the barycentric limit
// is only taken within 1e-12 of the size. Gradients lose digits as size / distance in the
// normalization, so within 1e-7 they are taken at a point moved towards the centroid.
constexpr double kSurfaceTol = 1e-12; ///< relative distance below which x is on the surface
constexpr double kGradientTol = 1e-7; ///< relative distance below which gradients move
constexpr double kGradientPush = 1e-6; ///< first relative move towards the centroid

Mat3 skew(const Vec3& e) {
    Mat3 s;
    s << 0, -e.z(), e.y(), e.z(), 0, -e.x(), -e.y(), e.x(), 0;
    return s;
}
} // namespace

MeanValueCell::MeanValueCell(const CellGeometry& cell)
    : MeanValueCell(cell.nodes, cell.loops) { }

MeanValueCell::MeanValueCell(std::vector<Vec3> nodes, const std::vector<std::vector<Index>>& loops)
    : m_nodes(std::move(nodes)) {
    if (m_nodes.size() < 4)
        throw MeshError(kNone, kNone, "a mean value cell needs at least 4 nodes");
    for (std::size_t f = 0; f < loops.size(); ++f) {
        if (loops[f].size() < 3)
            throw MeshError(kNone, long(f), "face with fewer than 3 nodes");
        for (Index v : loops[f])
            if (v < 0 || std::size_t(v) >= m_nodes.size())
                throw MeshError(kNone, long(f), "face node index out of range");
    }
    m_size = cell_size(m_nodes);
    m_volume = geometry::polyhedron_volume(m_nodes, loops);
    if (!(m_volume > 0))
        throw MeshError(kNone, kNone, "mean value cell of non-positive volume");
    m_centroid = geometry::polyhedron_centroid(m_nodes, loops);
    m_triangles = mean_value_triangulation(m_nodes, loops, 1e-14 * m_size * m_size);
    for (const auto& t : m_triangles) {
        const Vec3& a = m_nodes[std::size_t(t.nodes[0])];
        const Vec3 cr
            = (m_nodes[std::size_t(t.nodes[1])] - a).cross(m_nodes[std::size_t(t.nodes[2])] - a);
        m_tri_area.push_back(0.5 * cr.norm());
        m_tri_normal.push_back(cr.normalized());
    }
    std::map<std::array<Index, 2>, Index> edge_of;
    m_tri_edges.reserve(m_triangles.size());
    for (const auto& t : m_triangles) {
        std::array<Index, 3> sides {};
        for (std::size_t e = 0; e < 3; ++e) {
            const Index a = t.nodes[e], b = t.nodes[(e + 1) % 3];
            const std::array<Index, 2> key { std::min(a, b), std::max(a, b) };
            const auto [it, fresh] = edge_of.emplace(key, Index(m_edges.size()));
            if (fresh)
                m_edges.push_back(key);
            sides[e] = a < b ? it->second : -it->second - 1;
        }
        m_tri_edges.push_back(sides);
    }
}

bool MeanValueCell::evaluate_on_surface(const Vec3& x, VecX& phi, double rel_tol) const {
    const double tol = rel_tol * m_size;
    double best_dist = tol;
    std::size_t best = m_triangles.size();
    std::array<double, 3> best_bary {};
    for (std::size_t t = 0; t < m_triangles.size(); ++t) {
        const auto& tri = m_triangles[t].nodes;
        const Vec3& n = m_tri_normal[t];
        const double h = (x - m_nodes[std::size_t(tri[0])]).dot(n);
        if (std::abs(h) > best_dist)
            continue;
        const Vec3 y = x - h * n;
        std::array<double, 3> bary {};
        double sum = 0;
        for (int v = 0; v < 3; ++v) {
            const Vec3& b = m_nodes[std::size_t(tri[std::size_t((v + 1) % 3)])];
            const Vec3& c = m_nodes[std::size_t(tri[std::size_t((v + 2) % 3)])];
            bary[std::size_t(v)] = std::max(0.0, (b - y).cross(c - y).dot(n));
            sum += bary[std::size_t(v)];
        }
        if (!(sum > 0))
            continue;
        Vec3 z = Vec3::Zero();
        for (int v = 0; v < 3; ++v) {
            bary[std::size_t(v)] /= sum;
            z += bary[std::size_t(v)] * m_nodes[std::size_t(tri[std::size_t(v)])];
        }
        const double dist = (x - z).norm();
        if (dist <= best_dist) {
            best_dist = dist;
            best = t;
            best_bary = bary;
        }
    }
    if (best == m_triangles.size())
        return false;
    phi.setZero(Eigen::Index(m_nodes.size()));
    for (int v = 0; v < 3; ++v)
        phi[m_triangles[best].nodes[std::size_t(v)]] += best_bary[std::size_t(v)];
    return true;
}

void MeanValueCell::evaluate(const Vec3& x, VecX& phi, MatX3* grad) const {
    const bool near = evaluate_on_surface(x, phi, grad ? kGradientTol : kSurfaceTol);
    if (!near) {
        evaluate_interior(x, phi, grad);
        return;
    }
    if (!evaluate_on_surface(x, phi, kSurfaceTol))
        evaluate_interior(x, phi, nullptr);
    if (grad == nullptr)
        return;
    // 000 sec. 3.2.1: on the boundary the coordinates are the face's barycentric ones; the
    // gradient's normal component needs the interior, so take it just inside.
    VecX scratch;
    for (double eta = kGradientPush; eta < 0.5; eta *= 10) {
        const Vec3 y = x + eta * (m_centroid - x);
        if (!evaluate_on_surface(y, scratch, kGradientTol)) {
            evaluate_interior(y, scratch, grad);
            return;
        }
    }
    evaluate_interior(m_centroid, scratch, grad);
}

void MeanValueCell::evaluate_interior(const Vec3& x, VecX& phi, MatX3* grad) const {
    const std::size_t n = m_nodes.size();
    thread_local std::vector<Vec3> d, u;
    thread_local std::vector<double> r;
    d.resize(n);
    u.resize(n);
    r.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        d[v] = m_nodes[v] - x;
        r[v] = d[v].norm();
        u[v] = d[v] / r[v];
    }
    // Per edge (a, b), a < b: g = d_a x d_b, the angle theta it subtends at x, its term
    // theta / 2 n of the mean vector and, for the gradient, that term's Jacobian. A triangle side
    // from b to a takes them negated (g, n and both terms change sign, theta does not).
    struct EdgeTerms {
        Vec3 g, m;
        Mat3 J;
    };
    thread_local std::vector<EdgeTerms> terms;
    terms.resize(m_edges.size());
    const Mat3 I = Mat3::Identity();
    for (std::size_t k = 0; k < m_edges.size(); ++k) {
        const auto a = std::size_t(m_edges[k][0]), b = std::size_t(m_edges[k][1]);
        EdgeTerms& t = terms[k];
        t.g = d[a].cross(d[b]);
        const double gn = t.g.norm();
        const Vec3 nn = t.g / gn;
        const double th = std::atan2(gn, d[a].dot(d[b]));
        t.m = 0.5 * th * nn;
        if (!grad)
            continue;
        // d(d_v)/dx = -I; d(d_a x d_b)/dx = [x_b - x_a]_x; d(theta)/dx from the angle between
        // d_a and d_b; d(n)/dx = (I - n n^T) / |g| [x_b - x_a]_x.
        const Vec3 gth = nn.cross(u[a]) / r[a] + u[b].cross(nn) / r[b];
        t.J = 0.5 * (nn * gth.transpose())
            + (0.5 * th / gn) * (I - nn * nn.transpose()) * skew(m_nodes[b] - m_nodes[a]);
    }
    phi.setZero(Eigen::Index(n));
    if (grad)
        grad->setZero(Eigen::Index(n), 3);
    for (std::size_t f = 0; f < m_triangles.size(); ++f) {
        const auto& id = m_triangles[f].nodes;
        std::array<Vec3, 3> g;
        Vec3 m = Vec3::Zero();
        for (std::size_t e = 0; e < 3; ++e) {
            const Index k = m_tri_edges[f][e];
            const EdgeTerms& t = terms[std::size_t(k >= 0 ? k : -k - 1)];
            g[e] = k >= 0 ? t.g : Vec3(-t.g);
            m += k >= 0 ? t.m : Vec3(-t.m);
        }
        const double D = d[std::size_t(id[0])].dot(g[1]);
        // vertex v is opposite edge (v + 1) % 3
        std::array<double, 3> w {};
        for (std::size_t v = 0; v < 3; ++v) {
            w[v] = m.dot(g[(v + 1) % 3]) / D;
            phi[id[v]] += w[v];
        }
        if (!grad)
            continue;
        Mat3 Jm = Mat3::Zero();
        std::array<Vec3, 3> E;
        for (std::size_t e = 0; e < 3; ++e) {
            const Index k = m_tri_edges[f][e];
            const EdgeTerms& t = terms[std::size_t(k >= 0 ? k : -k - 1)];
            if (k >= 0)
                Jm += t.J;
            else
                Jm -= t.J;
            E[e] = m_nodes[std::size_t(id[(e + 1) % 3])] - m_nodes[std::size_t(id[e])];
        }
        const Vec3 gD = -(g[0] + g[1] + g[2]);
        for (std::size_t v = 0; v < 3; ++v) {
            const std::size_t o = (v + 1) % 3;
            const Vec3 gN = Jm.transpose() * g[o] + m.cross(E[o]);
            grad->row(id[v]) += ((gN - w[v] * gD) / D).transpose();
        }
    }
    const double W = phi.sum();
    phi /= W;
    if (grad) {
        const Eigen::RowVector3d gW = grad->colwise().sum();
        for (std::size_t v = 0; v < n; ++v)
            grad->row(Eigen::Index(v))
                = (grad->row(Eigen::Index(v)) - phi[Eigen::Index(v)] * gW) / W;
    }
}

VecX MeanValueCell::volume_fractions() const {
    // 000 eq. 14: mu_i = sum over the triangles at i of V(x_a, x_b, x_c, c) / (3 V).
    VecX mu = VecX::Zero(Eigen::Index(m_nodes.size()));
    for (const auto& tri : m_triangles) {
        const auto& id = tri.nodes;
        const Vec3 a = m_nodes[std::size_t(id[0])] - m_centroid;
        const Vec3 b = m_nodes[std::size_t(id[1])] - m_centroid;
        const Vec3 c = m_nodes[std::size_t(id[2])] - m_centroid;
        const double vol = a.dot(b.cross(c)) / 6.0;
        for (Index v : id)
            mu[v] += vol / (3.0 * m_volume);
    }
    return mu;
}

void mean_value(const std::vector<Vec3>& nodes, const std::vector<std::vector<Index>>& loops,
    const Vec3& x, VecX& phi, MatX3* grad) {
    MeanValueCell(nodes, loops).evaluate(x, phi, grad);
}

} // namespace polycut::basis
