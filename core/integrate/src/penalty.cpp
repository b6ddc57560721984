// Penalty points into reduced forces and system matrix blocks (penalty.hpp).
#include "polycut/integrate/penalty.hpp"

#include <algorithm>

namespace polycut::integrate {

namespace {
/// Velocity of a point: sum_i w_i v_i.
Vec3 point_velocity(const PenaltySet& set, const PenaltyPoint& p, const MatX3& v) {
    Vec3 out = Vec3::Zero();
    for (std::uint32_t k = p.first; k < p.first + p.count; ++k)
        out += set.weights[k] * v.row(set.nodes[k]).transpose();
    return out;
}

/// Position of (row, col) in A's values, or -1 when the pattern lacks it.
Index find_entry(const solve::SparseMatrix& A, Index row, Index col) {
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const int begin = outer[col];
    const int end = A.innerNonZeroPtr() ? begin + A.innerNonZeroPtr()[col] : outer[col + 1];
    const int* it = std::lower_bound(inner + begin, inner + end, int(row));
    if (it == inner + end || *it != row)
        return -1;
    return Index(it - inner);
}
} // namespace

void add_penalty_forces(const PenaltySet& set, const MatX3* v, double h,
    const std::vector<Index>& dof_map, double scale, VecX& f_r) {
    for (const PenaltyPoint& p : set.points) {
        Vec3 f = p.force;
        if (v) {
            const Vec3 pdot = point_velocity(set, p, *v);
            f -= h * (p.stiffness * pdot) + p.damping * (pdot - p.other_velocity);
        }
        f *= scale;
        for (std::uint32_t k = p.first; k < p.first + p.count; ++k)
            for (int c = 0; c < 3; ++c) {
                const std::size_t dof = 3 * std::size_t(set.nodes[k]) + std::size_t(c);
                if (dof < dof_map.size() && dof_map[dof] != kNone)
                    f_r(dof_map[dof]) += set.weights[k] * f(c);
            }
    }
}

std::size_t add_penalty_blocks(const PenaltySet& set, const std::vector<Index>& dof_map, double cK,
    double cD, solve::SparseMatrix& A, std::vector<std::pair<Index, double>>& record) {
    std::size_t missing = 0;
    double* values = A.valuePtr();
    for (const PenaltyPoint& p : set.points) {
        const Mat3 block = cK * p.stiffness + cD * p.damping;
        for (std::uint32_t a = p.first; a < p.first + p.count; ++a)
            for (std::uint32_t b = p.first; b < p.first + p.count; ++b) {
                const double w = set.weights[a] * set.weights[b];
                for (int r = 0; r < 3; ++r) {
                    const std::size_t dr = 3 * std::size_t(set.nodes[a]) + std::size_t(r);
                    if (dr >= dof_map.size() || dof_map[dr] == kNone)
                        continue;
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t dc = 3 * std::size_t(set.nodes[b]) + std::size_t(c);
                        const double value = w * block(r, c);
                        if (dc >= dof_map.size() || dof_map[dc] == kNone || value == 0)
                            continue;
                        const Index at = find_entry(A, dof_map[dr], dof_map[dc]);
                        if (at < 0) {
                            ++missing;
                            continue;
                        }
                        values[at] += value;
                        record.emplace_back(at, value);
                    }
                }
            }
    }
    return missing;
}

void undo_penalty_blocks(solve::SparseMatrix& A, std::vector<std::pair<Index, double>>& record) {
    double* values = A.valuePtr();
    for (const auto& [at, value] : record)
        values[at] -= value;
    record.clear();
}

void penalty_node_blocks(
    const PenaltySet& set, Index num_nodes, double cK, double cD, std::vector<Mat3>& blocks) {
    blocks.assign(std::size_t(num_nodes), Mat3::Zero());
    for (const PenaltyPoint& p : set.points) {
        const Mat3 block = cK * p.stiffness + cD * p.damping;
        for (std::uint32_t k = p.first; k < p.first + p.count; ++k)
            blocks[std::size_t(set.nodes[k])] += set.weights[k] * set.weights[k] * block;
    }
}

} // namespace polycut::integrate
