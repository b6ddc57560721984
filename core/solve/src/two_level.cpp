// Two-level preconditioner (two_level.hpp).
#include "two_level.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace polycut::solve::detail {

SolveStatus invert_diagonal_blocks(
    const SparseMatrix& A, const std::vector<long>& starts, std::vector<double>& inverse) {
    const long n = A.rows();
    if (starts.size() < 2 || starts.front() != 0 || starts.back() != n)
        return SolveStatus::NotReady;
    std::size_t total = 0;
    for (std::size_t b = 0; b + 1 < starts.size(); ++b) {
        const long size = starts[b + 1] - starts[b];
        total += std::size_t(size * size);
    }
    inverse.resize(total);
    const int* inner = A.innerIndexPtr();
    const double* values = A.valuePtr();
    std::size_t at = 0;
    Eigen::MatrixXd block;
    for (std::size_t b = 0; b + 1 < starts.size(); ++b) {
        const long s = starts[b], size = starts[b + 1] - s;
        block.setZero(size, size);
        for (long c = 0; c < size; ++c) {
            const int col = static_cast<int>(s + c);
            const int begin = A.outerIndexPtr()[col];
            const int end
                = A.isCompressed() ? A.outerIndexPtr()[col + 1] : begin + A.innerNonZeroPtr()[col];
            const int* it = std::lower_bound(inner + begin, inner + end, int(s));
            for (; it != inner + end && *it < s + size; ++it)
                block(*it - s, c) = values[it - inner];
        }
        if (!block.allFinite())
            return SolveStatus::NonFinite;
        const Eigen::LLT<Eigen::MatrixXd> llt(block);
        if (llt.info() != Eigen::Success)
            return SolveStatus::NotPositiveDefinite;
        Eigen::Map<Eigen::MatrixXd>(inverse.data() + at, size, size)
            = llt.solve(Eigen::MatrixXd::Identity(size, size));
        at += std::size_t(size * size);
    }
    return SolveStatus::Ok;
}

void TwoLevelPreconditioner::set_coarse_space(const SparseMatrix& P) {
    clear();
    m_P = P;
    m_P.makeCompressed();
    m_PT = m_P.transpose();
}

void TwoLevelPreconditioner::set_smoother(const std::vector<long>& starts, double omega) {
    if (starts != m_starts)
        m_size = -1;
    m_starts = starts;
    m_omega = omega;
}

void TwoLevelPreconditioner::clear() {
    m_size = -1;
    m_AP = SparseMatrix();
    m_APT = SparseMatrix();
    m_coarse = CholmodSolver();
}

SolveStatus TwoLevelPreconditioner::refresh_smoother(const SparseMatrix& A) {
    return invert_diagonal_blocks(A, m_starts, m_inverse);
}

SolveStatus TwoLevelPreconditioner::setup(const SparseMatrix& A) {
    m_size = -1;
    if (m_P.rows() != A.rows() || m_P.cols() < 1)
        return SolveStatus::NotReady;
    if (const SolveStatus s = refresh_smoother(A); s != SolveStatus::Ok)
        return s;
    m_AP = (A * m_P).pruned();
    m_AP.makeCompressed();
    m_APT = m_AP.transpose();
    SparseMatrix Ac = (m_PT * m_AP).pruned();
    // Symmetrise the round-off of the product (CHOLMOD reads one triangle) and lift the
    // directions a dependent P leaves without stiffness.
    Ac = 0.5 * (SparseMatrix(Ac.transpose()) + Ac);
    for (int k = 0; k < Ac.outerSize(); ++k)
        for (SparseMatrix::InnerIterator it(Ac, k); it; ++it)
            if (it.row() == it.col())
                it.valueRef() *= 1.0 + 1e-10;
    Ac.makeCompressed();
    if (const SolveStatus s = m_coarse.factorize(Ac); s != SolveStatus::Ok)
        return s;
    m_size = A.rows();
    return SolveStatus::Ok;
}

void TwoLevelPreconditioner::smooth(const Vector& r, Vector& out) const {
    out.resize(r.size());
    std::size_t at = 0;
    for (std::size_t b = 0; b + 1 < m_starts.size(); ++b) {
        const long s = m_starts[b], size = m_starts[b + 1] - s;
        out.segment(s, size).noalias() = m_omega
            * (Eigen::Map<const Eigen::MatrixXd>(m_inverse.data() + at, size, size)
                * r.segment(s, size));
        at += std::size_t(size * size);
    }
}

SolveStatus TwoLevelPreconditioner::apply(const Vector& r, Vector& z) {
    if (m_size != r.size())
        return SolveStatus::NotReady;
    // w = W r; g = P^T (r - A w); y = Ac^-1 g; z = w + P y - W A P y.
    smooth(r, m_w);
    m_g.noalias() = m_PT * r;
    m_g.noalias() -= m_APT * m_w;
    if (const SolveStatus s = m_coarse.solve(m_g, m_y); s != SolveStatus::Ok)
        return s;
    m_t.noalias() = m_AP * m_y;
    smooth(m_t, z);
    z = m_w - z;
    z.noalias() += m_P * m_y;
    return SolveStatus::Ok;
}

} // namespace polycut::solve::detail
