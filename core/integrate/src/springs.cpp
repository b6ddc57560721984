// Implicit penalty springs: forces, stiffness diagonal and energy (springs.hpp).
#include "polycut/integrate/springs.hpp"

#include <stdexcept>

namespace polycut::integrate {

void add_spring_forces(const std::vector<NodeSpring>& springs, const MatX3& x,
    const std::vector<Index>& dof_map, VecX& f_r) {
    for (const NodeSpring& s : springs) {
        if (s.node < 0 || s.node >= x.rows())
            continue;
        const Vec3 f = s.stiffness * (s.anchor - x.row(s.node).transpose());
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * std::size_t(s.node) + std::size_t(c);
            if (k < dof_map.size() && dof_map[k] != kNone)
                f_r(dof_map[k]) += f(c);
        }
    }
}

void spring_diagonal(const std::vector<NodeSpring>& springs, const std::vector<Index>& dof_map,
    Index n_free, VecX& diagonal) {
    diagonal.setZero(n_free);
    for (const NodeSpring& s : springs)
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * std::size_t(s.node) + std::size_t(c);
            if (s.node >= 0 && k < dof_map.size() && dof_map[k] != kNone)
                diagonal(dof_map[k]) += s.stiffness;
        }
}

double spring_energy(const std::vector<NodeSpring>& springs, const MatX3& x) {
    double e = 0;
    for (const NodeSpring& s : springs)
        if (s.node >= 0 && s.node < x.rows())
            e += 0.5 * s.stiffness * (s.anchor - x.row(s.node).transpose()).squaredNorm();
    return e;
}

void add_to_diagonal(solve::SparseMatrix& A, const VecX& d) {
    for (Index i = 0; i < d.size(); ++i) {
        if (d(i) == 0)
            continue;
        // coeffRef would insert a missing entry (and reallocate in the hot loop): refuse instead.
        const int col = int(i);
        double* entry = nullptr;
        for (solve::SparseMatrix::InnerIterator it(A, col); it; ++it)
            if (it.row() == col) {
                entry = &it.valueRef();
                break;
            }
        if (!entry)
            throw std::logic_error("add_to_diagonal: diagonal entry not stored");
        *entry += d(i);
    }
}

} // namespace polycut::integrate
