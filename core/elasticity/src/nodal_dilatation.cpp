#include "nodal_dilatation.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace polycut::elasticity::detail {

void NodalDilatation::rebuild(Index num_nodes, Index num_cells,
    const std::function<NodalCellView(Index)>& cell, double kappa, const PatternView& pattern) {
    m_kappa = kappa;
    const std::size_t nn = std::size_t(num_nodes), nc = std::size_t(num_cells);
    // Cells: mean divergence rows d_ek = (1/V) sum_q w_q grad phi_k(x_q), shifted to mean zero
    // (partition of unity makes the shift round-off for exact bases; it keeps theta_e exactly
    // blind to translations for approximate ones).
    m_cell_offset.assign(nc + 1, 0);
    for (std::size_t c = 0; c < nc; ++c)
        m_cell_offset[c + 1] = m_cell_offset[c] + cell(Index(c)).nodes->size();
    const std::size_t entries = m_cell_offset[nc];
    m_cell_nodes.resize(entries);
    m_div.assign(entries, Vec3::Zero());
    m_lumped.assign(entries, 0.0);
    m_c.assign(nc, 0.0);
    for (std::size_t c = 0; c < nc; ++c) {
        const NodalCellView v = cell(Index(c));
        const basis::CellIntegration& ci = *v.integration;
        const std::size_t o = m_cell_offset[c], n = v.nodes->size();
        double V = 0;
        for (std::size_t q = 0; q < ci.gradients.size(); ++q) {
            V += ci.weights[q];
            for (std::size_t k = 0; k < n; ++k)
                m_div[o + k] += ci.weights[q] * ci.gradients[q].row(Index(k)).transpose();
        }
        Vec3 mean = Vec3::Zero();
        for (std::size_t k = 0; k < n; ++k) {
            m_cell_nodes[o + k] = (*v.nodes)[k];
            m_div[o + k] /= V > 0 ? V : 1.0;
            mean += m_div[o + k];
            m_lumped[o + k]
                = ci.lumped_volume.size() == Index(n) ? ci.lumped_volume(Index(k)) : 0.0;
        }
        mean /= double(n > 0 ? n : 1);
        for (std::size_t k = 0; k < n; ++k) {
            m_div[o + k] -= mean;
            m_c[c] += m_div[o + k].dot(v.rest_local->row(Index(k)).transpose());
        }
    }
    // Nodes: volume V_a and incidences (cells around a, in cell order: deterministic sums).
    m_node_volume.assign(nn, 0.0);
    m_inc_offset.assign(nn + 1, 0);
    for (std::size_t e = 0; e < entries; ++e) {
        m_node_volume[std::size_t(m_cell_nodes[e])] += m_lumped[e];
        ++m_inc_offset[std::size_t(m_cell_nodes[e]) + 1];
    }
    std::partial_sum(m_inc_offset.begin(), m_inc_offset.end(), m_inc_offset.begin());
    m_inc_cell.resize(entries);
    m_inc_local.resize(entries);
    {
        std::vector<std::size_t> fill(m_inc_offset.begin(), m_inc_offset.end() - 1);
        for (std::size_t c = 0; c < nc; ++c)
            for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k) {
                const std::size_t s = fill[std::size_t(m_cell_nodes[k])]++;
                m_inc_cell[s] = Index(c);
                m_inc_local[s] = int(k - m_cell_offset[c]);
            }
    }
    // Patches: the sorted nodes of the cells around each node, and where each incident cell's
    // nodes sit in it.
    m_patch_offset.assign(nn + 1, 0);
    m_patch_nodes.clear();
    m_inc_pos_offset.assign(entries + 1, 0);
    m_inc_pos.clear();
    std::vector<std::size_t> stamp(nn, std::numeric_limits<std::size_t>::max());
    for (std::size_t a = 0; a < nn; ++a) {
        const std::size_t first = m_patch_nodes.size();
        for (std::size_t s = m_inc_offset[a]; s < m_inc_offset[a + 1]; ++s) {
            const std::size_t c = std::size_t(m_inc_cell[s]);
            for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k)
                if (const std::size_t i = std::size_t(m_cell_nodes[k]); stamp[i] != a) {
                    stamp[i] = a;
                    m_patch_nodes.push_back(Index(i));
                }
        }
        std::sort(m_patch_nodes.begin() + std::ptrdiff_t(first), m_patch_nodes.end());
        m_patch_offset[a + 1] = m_patch_nodes.size();
        const auto lo = m_patch_nodes.begin() + std::ptrdiff_t(first), hi = m_patch_nodes.end();
        for (std::size_t s = m_inc_offset[a]; s < m_inc_offset[a + 1]; ++s) {
            const std::size_t c = std::size_t(m_inc_cell[s]);
            for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k)
                m_inc_pos.push_back(int(std::lower_bound(lo, hi, m_cell_nodes[k]) - lo));
            m_inc_pos_offset[s + 1] = m_inc_pos.size();
        }
    }
    // Scatter into the pattern.
    m_rank.assign(nn, { -1, -1, -1 });
    m_length.assign(nn, 0);
    std::vector<Index> first_col(nn, kNone);
    for (std::size_t i = 0; i < nn; ++i) {
        signed char r = 0;
        for (std::size_t a = 0; a < 3; ++a)
            if (const Index d = pattern.dof_map[3 * i + a]; d != kNone) {
                m_rank[i][a] = r++;
                if (first_col[i] == kNone)
                    first_col[i] = d;
            }
        if (i < pattern.nb_length.size())
            m_length[i] = pattern.nb_length[i];
    }
    m_pair_offset.assign(nn + 1, 0);
    for (std::size_t a = 0; a < nn; ++a) {
        const std::size_t m = m_patch_offset[a + 1] - m_patch_offset[a];
        m_pair_offset[a + 1] = m_pair_offset[a] + m * m;
    }
    m_pair_slot.assign(m_pair_offset[nn], -1);
    for (std::size_t a = 0; a < nn; ++a) {
        const std::size_t p0 = m_patch_offset[a], m = m_patch_offset[a + 1] - p0;
        int* slot = m_pair_slot.data() + m_pair_offset[a];
        for (std::size_t q = 0; q < m; ++q) {
            const std::size_t j = std::size_t(m_patch_nodes[p0 + q]);
            if (first_col[j] == kNone)
                continue;
            const auto lo = pattern.nb_nodes.begin() + std::ptrdiff_t(pattern.nb_offset[j]);
            const auto hi = pattern.nb_nodes.begin() + std::ptrdiff_t(pattern.nb_offset[j + 1]);
            const int col = pattern.outer[std::size_t(first_col[j])];
            for (std::size_t p = 0; p < m; ++p) {
                const Index i = m_patch_nodes[p0 + p];
                if (first_col[std::size_t(i)] == kNone)
                    continue;
                const auto it = std::lower_bound(lo, hi, i);
                if (it == hi || *it != i)
                    throw StateError("NodalDilatation::rebuild",
                        "nodes " + std::to_string(i) + " and " + std::to_string(j)
                            + " share a patch but not a pattern column");
                slot[p * m + q]
                    = col + pattern.nb_start[std::size_t(it - pattern.nb_nodes.begin())];
            }
        }
    }
    m_theta_cell.resize(nc);
    m_rd.resize(entries);
    m_theta_node.resize(nn);
}

void NodalDilatation::cell_dilatations(
    const MatX3& x, std::span<const Mat3> rotations, bool corotated, bool rows) const {
    const std::size_t nc = m_c.size();
    for (std::size_t c = 0; c < nc; ++c) {
        const Mat3 R = corotated ? rotations[c] : Mat3::Identity();
        double theta = -m_c[c];
        for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k) {
            const Vec3 rd = R * m_div[k];
            theta += rd.dot(x.row(m_cell_nodes[k]).transpose());
            if (rows)
                m_rd[k] = rd;
        }
        m_theta_cell[c] = theta;
    }
}

double NodalDilatation::node_dilatation(std::size_t a) const {
    const double Va = m_node_volume[a];
    if (!(Va > 0))
        return 0.0;
    double theta = 0;
    for (std::size_t s = m_inc_offset[a]; s < m_inc_offset[a + 1]; ++s) {
        const std::size_t c = std::size_t(m_inc_cell[s]);
        theta += m_lumped[m_cell_offset[c] + std::size_t(m_inc_local[s])] * m_theta_cell[c];
    }
    return theta / Va;
}

void NodalDilatation::patch_gradient(
    std::size_t a, const std::vector<Vec3>& rows, std::vector<double>& beta) const {
    const double Va = m_node_volume[a];
    beta.assign(3 * (m_patch_offset[a + 1] - m_patch_offset[a]), 0.0);
    for (std::size_t s = m_inc_offset[a]; s < m_inc_offset[a + 1]; ++s) {
        const std::size_t c = std::size_t(m_inc_cell[s]);
        const std::size_t o = m_cell_offset[c];
        const double w = m_lumped[o + std::size_t(m_inc_local[s])] / Va;
        const int* pos = m_inc_pos.data() + m_inc_pos_offset[s];
        for (std::size_t k = 0; k < m_cell_offset[c + 1] - o; ++k)
            for (std::size_t d = 0; d < 3; ++d)
                beta[3 * std::size_t(pos[k]) + d] += w * rows[o + k](Index(d));
    }
}

void NodalDilatation::assemble(
    const MatX3& x, std::span<const Mat3> rotations, bool corotated, double* Kvals, double* fint) {
    cell_dilatations(x, rotations, corotated, true);
    const std::size_t nn = m_node_volume.size(), nc = m_c.size();
    for (std::size_t a = 0; a < nn; ++a)
        m_theta_node[a] = node_dilatation(a);
    if (fint) {
        // f_k = -sum_{e ∋ k} p_e R_e d_ek, p_e = kappa sum_{a in e} V_ae theta_a
        for (std::size_t c = 0; c < nc; ++c) {
            double p = 0;
            for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k)
                p += m_lumped[k] * m_theta_node[std::size_t(m_cell_nodes[k])];
            p *= m_kappa;
            for (std::size_t k = m_cell_offset[c]; k < m_cell_offset[c + 1]; ++k) {
                double* f = fint + 3 * std::size_t(m_cell_nodes[k]);
                f[0] -= p * m_rd[k].x();
                f[1] -= p * m_rd[k].y();
                f[2] -= p * m_rd[k].z();
            }
        }
    }
    if (!Kvals)
        return;
    // K += kappa V_a beta_a beta_a^T per node, beta_a = sum_{e ∋ a} (V_ae / V_a) R_e d_e.
    for (std::size_t a = 0; a < nn; ++a) {
        const double Va = m_node_volume[a];
        if (!(Va > 0))
            continue;
        const std::size_t p0 = m_patch_offset[a], m = m_patch_offset[a + 1] - p0;
        patch_gradient(a, m_rd, m_beta);
        const double scale = m_kappa * Va;
        const int* slot = m_pair_slot.data() + m_pair_offset[a];
        for (std::size_t q = 0; q < m; ++q) {
            const std::size_t j = std::size_t(m_patch_nodes[p0 + q]);
            for (std::size_t b = 0; b < 3; ++b) {
                const int rb = m_rank[j][b];
                if (rb < 0)
                    continue;
                const double sb = scale * m_beta[3 * q + b];
                for (std::size_t p = 0; p < m; ++p) {
                    const int base = slot[p * m + q];
                    if (base < 0)
                        continue;
                    const std::size_t i = std::size_t(m_patch_nodes[p0 + p]);
                    const int col = base + rb * m_length[j];
                    for (std::size_t ax = 0; ax < 3; ++ax)
                        if (const int ra = m_rank[i][ax]; ra >= 0)
                            Kvals[col + ra] += sb * m_beta[3 * p + ax];
                }
            }
        }
    }
}

double NodalDilatation::energy(
    const MatX3& x, std::span<const Mat3> rotations, bool corotated) const {
    cell_dilatations(x, rotations, corotated, false);
    double energy = 0;
    for (std::size_t a = 0; a < m_node_volume.size(); ++a) {
        const double theta = node_dilatation(a);
        energy += 0.5 * m_kappa * m_node_volume[a] * theta * theta;
    }
    return energy;
}

double NodalDilatation::omega2_bound(const VecX& nodal_mass) const {
    // Irons: K_vol = sum_a K_a, and the mass of node i split evenly over the patches holding it
    // (as many as its own patch has nodes: i in patch(a) iff a in patch(i)) gives
    // lambda_max(K_vol, M) <= max_a kappa V_a sum_i P_i |beta_ai|^2 / m_i, at rest (R = I).
    double bound = 0;
    std::vector<double> beta;
    for (std::size_t a = 0; a < m_node_volume.size(); ++a) {
        const double Va = m_node_volume[a];
        if (!(Va > 0))
            continue;
        const std::size_t p0 = m_patch_offset[a], m = m_patch_offset[a + 1] - p0;
        patch_gradient(a, m_div, beta);
        double sum = 0;
        for (std::size_t p = 0; p < m; ++p) {
            const std::size_t i = std::size_t(m_patch_nodes[p0 + p]);
            const double mi = nodal_mass(Index(i));
            const double b2 = beta[3 * p] * beta[3 * p] + beta[3 * p + 1] * beta[3 * p + 1]
                + beta[3 * p + 2] * beta[3 * p + 2];
            if (b2 == 0)
                continue;
            if (!(mi > 0))
                return std::numeric_limits<double>::infinity();
            sum += double(m_patch_offset[i + 1] - m_patch_offset[i]) * b2 / mi;
        }
        bound = std::max(bound, m_kappa * Va * sum);
    }
    return bound;
}

} // namespace polycut::elasticity::detail
