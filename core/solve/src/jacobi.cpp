// Jacobi and 3x3 node-block Jacobi set-ups of PCG (pcg.cpp): the inverse diagonal, and the
// inverse 3x3 diagonal blocks of a matrix whose DOFs come in node triples.
#include "jacobi.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace polycut::solve::detail {
namespace {

/// Position of entry (row, col) in compressed column storage, or -1.
long find_entry(const SparseMatrix& A, int row, int col) {
    const int* inner = A.innerIndexPtr();
    const int begin = A.outerIndexPtr()[col];
    const int end
        = A.isCompressed() ? A.outerIndexPtr()[col + 1] : begin + A.innerNonZeroPtr()[col];
    const int* it = std::lower_bound(inner + begin, inner + end, row);
    return (it != inner + end && *it == row) ? it - inner : -1;
}

} // namespace

SolveStatus invert_diagonal(const SparseMatrix& A, Vector& inv_diag) {
    const long n = A.rows();
    inv_diag.resize(n);
    for (long j = 0; j < n; ++j) {
        const long k = find_entry(A, static_cast<int>(j), static_cast<int>(j));
        const double d = k < 0 ? 0.0 : A.valuePtr()[k];
        if (!std::isfinite(d))
            return SolveStatus::NonFinite;
        if (!(d > 0))
            return SolveStatus::NotPositiveDefinite;
        inv_diag[j] = 1.0 / d;
    }
    return SolveStatus::Ok;
}

SolveStatus invert_node_blocks(
    const SparseMatrix& A, std::vector<Eigen::Matrix3d>& inv_blocks, Vector& inv_diag) {
    const long n = A.rows();
    const long blocks = n / 3;
    inv_blocks.resize(static_cast<size_t>(blocks));
    const int* inner = A.innerIndexPtr();
    const double* values = A.valuePtr();
    for (long b = 0; b < blocks; ++b) {
        Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
        for (int c = 0; c < 3; ++c) {
            const int col = static_cast<int>(3 * b + c);
            const int begin = A.outerIndexPtr()[col];
            const int end
                = A.isCompressed() ? A.outerIndexPtr()[col + 1] : begin + A.innerNonZeroPtr()[col];
            const int* it = std::lower_bound(inner + begin, inner + end, 3 * b);
            for (; it != inner + end && *it < 3 * b + 3; ++it)
                block(*it - 3 * b, c) = values[it - inner];
        }
        if (!block.allFinite())
            return SolveStatus::NonFinite;
        // a diagonal block of an SPD matrix is SPD
        const Eigen::LLT<Eigen::Matrix3d> llt(block);
        if (llt.info() != Eigen::Success)
            return SolveStatus::NotPositiveDefinite;
        inv_blocks[static_cast<size_t>(b)] = llt.solve(Eigen::Matrix3d::Identity());
    }
    // trailing rows that do not fill a node block: scalar Jacobi
    inv_diag.resize(n);
    for (long j = 3 * blocks; j < n; ++j) {
        const long k = find_entry(A, static_cast<int>(j), static_cast<int>(j));
        const double d = k < 0 ? 0.0 : values[k];
        if (!(d > 0))
            return std::isfinite(d) ? SolveStatus::NotPositiveDefinite : SolveStatus::NonFinite;
        inv_diag[j] = 1.0 / d;
    }
    return SolveStatus::Ok;
}

} // namespace polycut::solve::detail
