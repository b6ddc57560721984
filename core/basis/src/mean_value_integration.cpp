// Integration of mean value cells: the sample heuristic of seed 000 eq. 14-16 and a reference
// Gauss rule on the centroid tetrahedralization; lumped volumes from 000 eq. 18.
#include "polycut/basis/mean_value.hpp"
#include "polycut/common/error.hpp"
#include "star_rule.hpp"

#include <algorithm>

namespace polycut::basis {

namespace {
/// The rules weight samples by signed volumes of (surface triangle, centroid) tets, which are
/// all positive when the cell is star-shaped from its centroid. A cell a cut or a sliver merge
/// left slightly non-convex (CutOptions::convex_tol) or with a face bent by snapping has a few
/// negative ones: a negative weight makes the stiffness indefinite and a negative lumped volume
/// a negative mass, and PCG then stalls (2,000-4,000 iterations, "not positive definite") on an
/// organ re-cut along its cut (issue 12). Negative weights are dropped and the rest scaled to
/// keep their sum; untouched when none is negative.
void drop_negative(std::vector<double>& w) {
    double total = 0, positive = 0;
    bool negative = false;
    for (double x : w) {
        total += x;
        positive += std::max(x, 0.0);
        negative = negative || x < 0;
    }
    if (!negative || !(positive > 0) || !(total > 0))
        return;
    for (double& x : w)
        x = std::max(x, 0.0) * (total / positive);
}

/// Lumped volume fractions (000 eq. 14) with the same repair, and each at least 1 % of the
/// mean share, so that no node of the cell has zero or negative mass.
VecX positive_fractions(VecX mu) {
    const double floor = 0.01 / double(mu.size());
    if (mu.minCoeff() >= floor)
        return mu;
    const double total = mu.sum();
    mu = mu.cwiseMax(floor);
    return mu * (total / mu.sum());
}
} // namespace

CellIntegration MeanValueCell::integrate(MvcRule rule, int gauss_degree) const {
    CellIntegration out;
    const VecX mu = positive_fractions(volume_fractions());
    out.lumped_volume = mu * m_volume; // 000 eq. 18
    const bool tet = m_nodes.size() == 4 && m_triangles.size() == 4;
    if (tet) {
        // 000 sec. 3.4: a tet is P1, one point is exact.
        out.points.push_back(m_centroid);
        out.weights.push_back(m_volume);
    } else if (rule == MvcRule::Heuristic) {
        // 000 eq. 14-16: a sample at 0.8 x_i + 0.2 c per node with weight mu_i V / 2 and a
        // sample at 0.9 c_f + 0.1 c per surface triangle with weight kappa_f V / 2, where
        // kappa_f V is the volume of the tet (triangle, c). Both sets of weights sum to V / 2.
        for (std::size_t v = 0; v < m_nodes.size(); ++v) {
            out.points.push_back(0.8 * m_nodes[v] + 0.2 * m_centroid);
            out.weights.push_back(0.5 * mu[Eigen::Index(v)] * m_volume);
        }
        for (const auto& tri : m_triangles) {
            const Vec3& a = m_nodes[std::size_t(tri.nodes[0])];
            const Vec3& b = m_nodes[std::size_t(tri.nodes[1])];
            const Vec3& c = m_nodes[std::size_t(tri.nodes[2])];
            const double vol = (a - m_centroid).dot((b - m_centroid).cross(c - m_centroid)) / 6.0;
            out.points.push_back(0.9 * (a + b + c) / 3.0 + 0.1 * m_centroid);
            out.weights.push_back(0.5 * vol);
        }
    } else {
        std::vector<std::array<Index, 3>> tris;
        tris.reserve(m_triangles.size());
        for (const auto& t : m_triangles)
            tris.push_back(t.nodes);
        detail::star_rule(m_nodes, tris, m_centroid, gauss_degree, out.points, out.weights);
    }
    drop_negative(out.weights);
    out.gradients.resize(out.points.size());
    VecX phi;
    for (std::size_t q = 0; q < out.points.size(); ++q)
        evaluate(out.points[q], phi, &out.gradients[q]);
    return out;
}

CellIntegration integrate_mean_value(const std::vector<Vec3>& nodes,
    const std::vector<std::vector<Index>>& loops, MvcRule rule, int gauss_degree) {
    return MeanValueCell(nodes, loops).integrate(rule, gauss_degree);
}

CellIntegration integrate_mean_value(
    const mesh::Mesh& mesh, Index cell, MvcRule rule, int gauss_degree) {
    try {
        return MeanValueCell(cell_geometry(mesh, cell)).integrate(rule, gauss_degree);
    } catch (const MeshError& e) {
        throw MeshError(cell, e.face(), e.problem());
    }
}

} // namespace polycut::basis
