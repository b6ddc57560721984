// Test cells for the polyhedral bases (mean value and harmonic): convex hulls of point sets,
// a cut cube, a slanted split of a hex into two glued cells with collinear and coplanar faces,
// a 24-node truncated octahedron, a 12-gon prism and a non-convex L-shaped prism; plus the
// isotropic elasticity matrix and the stiffness matrix Ke = sum_q w_q B_q^T C B_q.
#pragma once

#include "polycut/basis/cell_geometry.hpp"
#include "polycut/basis/cell_integration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace polycut::basis::testing {

/// Convex hull of points in convex position (every point a vertex or on an edge/face):
/// coplanar points form one face, loops ordered outward.
inline CellGeometry convex_cell(const std::vector<Vec3>& pts) {
    const std::size_t n = pts.size();
    double size = 0;
    for (const auto& p : pts)
        for (const auto& q : pts)
            size = std::max(size, (p - q).norm());
    const double tol = 1e-9 * size;
    std::set<std::vector<Index>> seen;
    CellGeometry cell { pts, {} };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (std::size_t k = j + 1; k < n; ++k) {
                Vec3 nrm = (pts[j] - pts[i]).cross(pts[k] - pts[i]);
                if (nrm.norm() < 1e-9 * size * size)
                    continue;
                nrm.normalize();
                int above = 0, below = 0;
                std::vector<Index> on;
                for (std::size_t l = 0; l < n; ++l) {
                    const double h = (pts[l] - pts[i]).dot(nrm);
                    if (h > tol)
                        ++above;
                    else if (h < -tol)
                        ++below;
                    else
                        on.push_back(Index(l));
                }
                if (above > 0 && below > 0)
                    continue;
                if (above > 0)
                    nrm = -nrm;
                if (!seen.insert(on).second)
                    continue;
                Vec3 c = Vec3::Zero();
                for (Index l : on)
                    c += pts[std::size_t(l)];
                c /= double(on.size());
                const Vec3 e1 = (pts[std::size_t(on[0])] - c).normalized();
                const Vec3 e2 = nrm.cross(e1);
                std::sort(on.begin(), on.end(), [&](Index a, Index b) {
                    const Vec3 da = pts[std::size_t(a)] - c, db = pts[std::size_t(b)] - c;
                    return std::atan2(da.dot(e2), da.dot(e1)) < std::atan2(db.dot(e2), db.dot(e1));
                });
                cell.loops.push_back(on);
            }
    return cell;
}

inline std::vector<Vec3> box_corners(const Vec3& lo, const Vec3& hi) {
    std::vector<Vec3> p;
    for (int k = 0; k < 8; ++k)
        p.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
    return p;
}

inline CellGeometry unit_tet() {
    return convex_cell(
        { Vec3(0.1, 0.0, 0.0), Vec3(1.0, 0.2, 0.1), Vec3(0.3, 0.9, 0.0), Vec3(0.4, 0.3, 1.1) });
}

/// A 2 x 1.5 x 1 box [m].
inline CellGeometry cube() {
    return convex_cell(box_corners(Vec3(0, 0, 0), Vec3(2, 1.5, 1)));
}

/// Unit cube with the corner (1, 1, 1) cut off by x + y + z = 2.5: 10 nodes, 7 faces.
inline CellGeometry cut_cube() {
    auto p = box_corners(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.pop_back();
    p.emplace_back(0.5, 1, 1);
    p.emplace_back(1, 0.5, 1);
    p.emplace_back(1, 1, 0.5);
    return convex_cell(p);
}

/// Truncated octahedron: the 24 permutations of (0, +-1, +-2) scaled by 0.5 [m].
inline CellGeometry truncated_octahedron() {
    std::vector<Vec3> p;
    const int perm[6][3]
        = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
    for (const auto& pr : perm)
        for (int s1 : { -1, 1 })
            for (int s2 : { -1, 1 }) {
                double v[3] = { 0, 0, 0 };
                v[pr[1]] = s1 * 1.0;
                v[pr[2]] = s2 * 2.0;
                p.emplace_back(0.5 * v[0], 0.5 * v[1], 0.5 * v[2]);
            }
    return convex_cell(p);
}

/// Prism over a regular 12-gon of circumradius 1, height 0.7 [m]: 24 nodes.
inline CellGeometry prism12() {
    std::vector<Vec3> p;
    for (int z = 0; z < 2; ++z)
        for (int k = 0; k < 12; ++k) {
            const double a = 2 * std::numbers::pi * k / 12;
            p.emplace_back(std::cos(a), std::sin(a), 0.7 * z);
        }
    return convex_cell(p);
}

/// Splits face f of `cell` into two faces along the chord between its nodes a and b.
inline void split_face(CellGeometry& cell, std::size_t f, Index a, Index b) {
    auto loop = cell.loops[f];
    const auto ia = std::size_t(std::find(loop.begin(), loop.end(), a) - loop.begin());
    std::rotate(loop.begin(), loop.begin() + long(ia), loop.end());
    const auto ib = std::size_t(std::find(loop.begin(), loop.end(), b) - loop.begin());
    std::vector<Index> first(loop.begin(), loop.begin() + long(ib) + 1);
    std::vector<Index> second(loop.begin() + long(ib), loop.end());
    second.push_back(a);
    cell.loops[f] = first;
    cell.loops.push_back(second);
}

/// Several cells on shared global nodes.
struct GluedCells {
    std::vector<Vec3> nodes;
    std::vector<std::vector<Index>> cell_nodes; ///< global node of each local node
    std::vector<CellGeometry> cells; ///< local geometry
};

/// Adds a convex cell from global node ids.
inline void add_convex(GluedCells& g, const std::vector<Index>& ids) {
    std::vector<Vec3> p;
    for (Index i : ids)
        p.push_back(g.nodes[std::size_t(i)]);
    g.cells.push_back(convex_cell(p));
    g.cell_nodes.push_back(ids);
}

/// Local index of global node `global` in cell c.
inline Index local_of(const GluedCells& g, std::size_t c, Index global) {
    const auto& ids = g.cell_nodes[c];
    return Index(std::find(ids.begin(), ids.end(), global) - ids.begin());
}

/// The unit cube split by the slanted plane z = 0.3 + 0.4 x into two convex cells. The split
/// face carries collinear nodes at (0.5, 0/1, 0.5) and is itself split into two coplanar quads
/// along the chord between them; the lower cell has a collinear node at (0.5, 0, 0).
/// With `three`, the upper cell is split again by y = 0.5 (so a node pair is interior-ish).
inline GluedCells slanted_split_hex() {
    GluedCells g;
    g.nodes = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), // 0-3 bottom
        Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1), Vec3(1, 1, 1), // 4-7 top
        Vec3(0, 0, 0.3), Vec3(1, 0, 0.7), Vec3(0, 1, 0.3), Vec3(1, 1, 0.7), // 8-11 split
        Vec3(0.5, 0, 0.5), Vec3(0.5, 1, 0.5), // 12-13 collinear
        Vec3(0.5, 0, 0) }; // 14 collinear
    add_convex(g, { 0, 1, 2, 3, 8, 9, 10, 11, 12, 13, 14 });
    add_convex(g, { 4, 5, 6, 7, 8, 9, 10, 11, 12, 13 });
    // split the shared face in both cells along the chord 12-13 into two coplanar quads
    for (std::size_t c = 0; c < 2; ++c) {
        const Index a = local_of(g, c, 12), b = local_of(g, c, 13);
        for (std::size_t f = 0; f < g.cells[c].loops.size(); ++f) {
            const auto& l = g.cells[c].loops[f];
            if (l.size() == 6 && std::count(l.begin(), l.end(), a)
                && std::count(l.begin(), l.end(), b)) {
                split_face(g.cells[c], f, a, b);
                break;
            }
        }
    }
    return g;
}

/// Non-convex L-shaped prism: L = (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) extruded over z in [0, 1].
inline CellGeometry l_prism() {
    const double xy[6][2] = { { 0, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1, 2 }, { 0, 2 } };
    CellGeometry c;
    for (int z = 0; z < 2; ++z)
        for (const auto& q : xy)
            c.nodes.emplace_back(q[0], q[1], double(z));
    c.loops.push_back({ 5, 4, 3, 2, 1, 0 });
    c.loops.push_back({ 6, 7, 8, 9, 10, 11 });
    for (Index k = 0; k < 6; ++k) {
        const Index k1 = (k + 1) % 6;
        c.loops.push_back({ k, k1, Index(k1 + 6), Index(k + 6) });
    }
    return c;
}

/// Isotropic elasticity matrix (6 x 6), Voigt order xx yy zz xy yz zx, engineering shears.
inline Eigen::Matrix<double, 6, 6> isotropic_c(double young, double poisson) {
    const double lambda = young * poisson / ((1 + poisson) * (1 - 2 * poisson));
    const double mu = young / (2 * (1 + poisson));
    Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
    C.topLeftCorner<3, 3>().setConstant(lambda);
    C.topLeftCorner<3, 3>().diagonal().array() += 2 * mu;
    C.bottomRightCorner<3, 3>().diagonal().setConstant(mu);
    return C;
}

/// Strain-displacement matrix (6 x 3n) from gradients (n x 3).
inline MatX strain_matrix(const MatX3& grad) {
    MatX B = MatX::Zero(6, 3 * grad.rows());
    for (Eigen::Index i = 0; i < grad.rows(); ++i) {
        const double gx = grad(i, 0), gy = grad(i, 1), gz = grad(i, 2);
        B(0, 3 * i) = gx;
        B(1, 3 * i + 1) = gy;
        B(2, 3 * i + 2) = gz;
        B(3, 3 * i) = gy;
        B(3, 3 * i + 1) = gx;
        B(4, 3 * i + 1) = gz;
        B(4, 3 * i + 2) = gy;
        B(5, 3 * i) = gz;
        B(5, 3 * i + 2) = gx;
    }
    return B;
}

/// Ke = sum_q w_q B_q^T C B_q (3n x 3n).
inline MatX stiffness(const CellIntegration& ci, const Eigen::Matrix<double, 6, 6>& C) {
    const auto n = ci.gradients.empty() ? 0 : ci.gradients[0].rows();
    MatX K = MatX::Zero(3 * n, 3 * n);
    for (std::size_t q = 0; q < ci.points.size(); ++q) {
        const MatX B = strain_matrix(ci.gradients[q]);
        K.noalias() += ci.weights[q] * B.transpose() * C * B;
    }
    return K;
}

/// Stress (Voigt) of the displacement field u = G x.
inline Eigen::Matrix<double, 6, 1> stress_of(const Mat3& G, const Eigen::Matrix<double, 6, 6>& C) {
    Eigen::Matrix<double, 6, 1> eps;
    eps << G(0, 0), G(1, 1), G(2, 2), G(0, 1) + G(1, 0), G(1, 2) + G(2, 1), G(2, 0) + G(0, 2);
    return C * eps;
}

inline Mat3 voigt_to_tensor(const Eigen::Matrix<double, 6, 1>& s) {
    Mat3 S;
    S << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
    return S;
}

} // namespace polycut::basis::testing
