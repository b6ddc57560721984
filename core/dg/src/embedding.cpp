// Stitching and MLS embedding of a DG field (embedding.hpp, 003 sec. 8).
#include "polycut/dg/embedding.hpp"

#include "polycut/dg/dg_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace polycut::dg {

Stitching::Stitching(const DgModel& model)
    : m_model(&model) {
    const mesh::Mesh& m = model.mesh();
    const Index n_nodes = m.num_nodes();
    std::vector<int> count(std::size_t(n_nodes), 0);
    for (const mesh::Cell& cell : m.cells)
        for (Index n : cell.nodes)
            ++count[std::size_t(n)];
    m_used.assign(std::size_t(n_nodes), 0);
    std::vector<Eigen::Triplet<double, int>> t;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const CellBasis& b = model.basis(c);
        for (Index n : m.cells[std::size_t(c)].nodes) {
            m_used[std::size_t(n)] = 1;
            const VecX phi = b.values(m.rest[std::size_t(n)]);
            const double w = 1.0 / double(count[std::size_t(n)]); // 003 eq. 17: 1 / |N_i|
            for (int i = 0; i < b.size(); ++i)
                t.emplace_back(int(n), int(model.offset(c) + i), w * phi[i]);
        }
    }
    m_S.resize(int(n_nodes), int(model.num_coefficients()));
    m_S.setFromTriplets(t.begin(), t.end());
    m_S.makeCompressed();
}

void Stitching::displacements(const MatX3& x, MatX3& u) const {
    u.noalias() = m_S * (x - m_model->rest());
}

void Stitching::positions(const MatX3& x, std::vector<Vec3>& out) const {
    MatX3 u;
    displacements(x, u);
    const auto& rest = m_model->mesh().rest;
    out.resize(rest.size());
    for (std::size_t i = 0; i < rest.size(); ++i)
        out[i] = rest[i] + u.row(Index(i)).transpose();
}

void Stitching::loads(const VecX& nodal_forces, VecX& coefficient_loads) const {
    // f_coeff = S^T f_nodes per axis (the flat vectors are row-major: 3 node + axis).
    const Index nn = m_S.rows();
    const auto F = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        nodal_forces.data(), nn, 3);
    const MatX3 G = m_S.transpose() * F;
    coefficient_loads = flat(G);
}

MlsEmbedding::MlsEmbedding(const DgModel& model, const std::vector<Vec3>& points, double support) {
    const mesh::Mesh& m = model.mesh();
    std::vector<std::uint8_t> used(m.rest.size(), 0);
    for (const mesh::Cell& cell : m.cells)
        for (Index n : cell.nodes)
            used[std::size_t(n)] = 1;
    // Cell diameters and centroids, to scale each point's support to the local sampling.
    std::vector<double> diameter(std::size_t(m.num_cells()), 0.0);
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& nodes = m.cells[std::size_t(c)].nodes;
        for (std::size_t a = 0; a < nodes.size(); ++a)
            for (std::size_t b = a + 1; b < nodes.size(); ++b)
                diameter[std::size_t(c)] = std::max(diameter[std::size_t(c)],
                    (m.rest[std::size_t(nodes[a])] - m.rest[std::size_t(nodes[b])]).norm());
    }
    std::vector<Eigen::Triplet<double, int>> t;
    for (std::size_t p = 0; p < points.size(); ++p) {
        const Vec3& X = points[p];
        Index nearest = kNone;
        double best = std::numeric_limits<double>::infinity();
        for (Index c = 0; c < m.num_cells(); ++c) {
            const double d = (model.basis(c).center - X).squaredNorm();
            if (d < best) {
                best = d;
                nearest = c;
            }
        }
        if (nearest == kNone)
            continue;
        double rho = support * diameter[std::size_t(nearest)];
        for (int attempt = 0; attempt < 5; ++attempt, rho *= 2) {
            // A(x) = sum theta_i P_i P_i^T with P_i = (1, (x_i - p) / rho): centred and scaled
            // so that its condition number measures the geometry, not the units.
            Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
            std::vector<std::pair<Index, double>> near;
            for (std::size_t i = 0; i < m.rest.size(); ++i) {
                if (!used[i])
                    continue;
                const double d = (m.rest[i] - X).norm();
                if (d >= rho)
                    continue;
                const double theta = std::exp(-std::pow(3.0 * d / rho, 2));
                Eigen::Vector4d P;
                P << 1.0, (m.rest[i] - X) / rho;
                A += theta * P * P.transpose();
                near.emplace_back(Index(i), theta);
            }
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
            const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
            if (near.size() < 4 || !(lo > 1e-8 * hi))
                continue;
            // u(p) = a^T P(p), P(p) = (1, 0, 0, 0): w_i = theta_i e_0^T A^-1 P_i (003 eq. 19).
            const Eigen::Vector4d row = A.ldlt().solve(Eigen::Vector4d::UnitX());
            for (const auto& [i, theta] : near) {
                Eigen::Vector4d P;
                P << 1.0, (m.rest[std::size_t(i)] - X) / rho;
                t.emplace_back(int(p), int(i), theta * row.dot(P));
            }
            break;
        }
    }
    m_W.resize(int(points.size()), int(m.num_nodes()));
    m_W.setFromTriplets(t.begin(), t.end());
    m_W.makeCompressed();
}

void MlsEmbedding::displacements(const MatX3& stitched, MatX3& u) const {
    u.noalias() = m_W * stitched;
}

} // namespace polycut::dg
