// The finest level of the V-cycle by 3x3 node blocks (see amg_cycle.hpp, "Node blocks").
//
// An elasticity matrix whose free DOFs come as whole nodes (x, y, z consecutive) stores, in
// each of a node's three columns 3I, 3I + 1, 3I + 2, the same rows, in triples 3J, 3J + 1,
// 3J + 2. The matrix is symmetric, so column 3I + b is row 3I + b and the 3x3 block A_IJ sits at
// positions k, k + 1, k + 2 of the node's three columns. The block-CSR copy puts each block's
// nine values side by side. Block Gauss-Seidel solves the diagonal block per node:
// x_I = D_I^-1 (b_I - sum_{J != I} A_IJ x_J).
#include "amg_cycle.hpp"

#include <algorithm>
#include <cmath>

namespace polycut::solve::detail {

namespace {

/// s += sum_{k in [begin, end)} A_k x_{column[k]}, A_k row-major 3x3.
[[gnu::always_inline]] inline void add_blocks(
    const double* value, const int* column, const double* x, int begin, int end, double s[3]) {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int k = begin; k < end; ++k) {
        const double* xj = x + column[k];
        const double* a = value + 9 * std::size_t(k);
        const double x0 = xj[0], x1 = xj[1], x2 = xj[2];
        s0 += a[0] * x0 + a[1] * x1 + a[2] * x2;
        s1 += a[3] * x0 + a[4] * x1 + a[5] * x2;
        s2 += a[6] * x0 + a[7] * x1 + a[8] * x2;
    }
    s[0] += s0;
    s[1] += s1;
    s[2] += s2;
}

/// y = M s for a row-major 3x3 M.
[[gnu::always_inline]] inline void apply3(const double* m, const double s[3], double* y) {
    y[0] = m[0] * s[0] + m[1] * s[1] + m[2] * s[2];
    y[1] = m[3] * s[0] + m[4] * s[1] + m[5] * s[2];
    y[2] = m[6] * s[0] + m[7] * s[1] + m[8] * s[2];
}

/// inv = d^-1 for a symmetric positive definite 3x3 d (row-major); false if it is not.
bool invert_spd3(const double d[9], double* inv) {
    const double c00 = d[4] * d[8] - d[5] * d[7];
    const double c01 = d[5] * d[6] - d[3] * d[8];
    const double c02 = d[3] * d[7] - d[4] * d[6];
    const double det = d[0] * c00 + d[1] * c01 + d[2] * c02;
    // leading minors positive (Sylvester)
    if (!(d[0] > 0) || !(d[0] * d[4] - d[1] * d[3] > 0) || !(det > 0) || !std::isfinite(det))
        return false;
    const double s = 1.0 / det;
    inv[0] = c00 * s;
    inv[1] = (d[2] * d[7] - d[1] * d[8]) * s;
    inv[2] = (d[1] * d[5] - d[2] * d[4]) * s;
    inv[3] = c01 * s;
    inv[4] = (d[0] * d[8] - d[2] * d[6]) * s;
    inv[5] = (d[2] * d[3] - d[0] * d[5]) * s;
    inv[6] = c02 * s;
    inv[7] = (d[1] * d[6] - d[0] * d[7]) * s;
    inv[8] = (d[0] * d[4] - d[1] * d[3]) * s;
    return true;
}

} // namespace

bool AmgCycle::find_node_blocks(const SparseMatrix& A) {
    m_node_ptr.clear();
    m_node_column.clear();
    m_node_diagonal.clear();
    m_blocks_stale = true;
    const long n = A.rows();
    if (n % 3 != 0 || n == 0)
        return false;
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const long nodes = n / 3;
    std::vector<int> ptr(std::size_t(nodes) + 1, 0), column, diagonal(std::size_t(nodes), -1);
    column.reserve(std::size_t(A.nonZeros() / 9));
    for (long I = 0; I < nodes; ++I) {
        const int c = int(3 * I);
        const int len = outer[c + 1] - outer[c];
        if (len % 3 != 0 || outer[c + 2] - outer[c + 1] != len
            || outer[c + 3] - outer[c + 2] != len)
            return false;
        const int* rows0 = inner + outer[c];
        for (int b = 0; b < 3; ++b) {
            const int* rows = inner + outer[c + b];
            for (int k = 0; k < len; k += 3) {
                const int r = rows[k];
                if (r % 3 != 0 || rows[k + 1] != r + 1 || rows[k + 2] != r + 2 || r != rows0[k])
                    return false;
            }
        }
        for (int k = 0; k < len; k += 3) {
            if (rows0[k] == c)
                diagonal[std::size_t(I)] = int(column.size());
            column.push_back(rows0[k]);
        }
        if (diagonal[std::size_t(I)] < 0)
            return false;
        ptr[std::size_t(I) + 1] = int(column.size());
    }
    m_node_ptr = std::move(ptr);
    m_node_column = std::move(column);
    m_node_diagonal = std::move(diagonal);
    m_node_value.resize(9 * m_node_column.size());
    m_node_inverse.resize(9 * std::size_t(nodes));
    return true;
}

void AmgCycle::find_node_block_ranges() {
    m_node_own_begin.clear();
    m_node_own_end.clear();
    if (m_node_ptr.empty() || m_threads <= 1)
        return;
    const std::size_t nodes = m_node_diagonal.size();
    m_node_own_begin.resize(nodes);
    m_node_own_end.resize(nodes);
    for (int t = 0; t < m_threads; ++t) {
        const int lo = m_block_rows[std::size_t(t)], hi = m_block_rows[std::size_t(t) + 1];
        for (int I = lo / 3; I < hi / 3; ++I) {
            const int* begin = m_node_column.data() + m_node_ptr[std::size_t(I)];
            const int* end = m_node_column.data() + m_node_ptr[std::size_t(I) + 1];
            m_node_own_begin[std::size_t(I)]
                = int(std::lower_bound(begin, end, lo) - m_node_column.data());
            m_node_own_end[std::size_t(I)]
                = int(std::lower_bound(begin, end, hi) - m_node_column.data());
        }
    }
}

bool AmgCycle::refresh_node_blocks(const SparseMatrix& A) {
    const long nodes = long(m_node_diagonal.size());
    const int* outer = A.outerIndexPtr();
    const double* values = A.valuePtr();
    const bool hybrid = m_threads > 1;
    if (hybrid)
        m_fine_l1.setZero(3 * nodes);
    bool ok = true;
#pragma omp parallel for num_threads(m_threads) schedule(static) reduction(&& : ok) if (hybrid)
    for (long I = 0; I < nodes; ++I) {
        const int first = m_node_ptr[std::size_t(I)], last = m_node_ptr[std::size_t(I) + 1];
        // block k's row b is column 3I + b at position 3 (k - first) (the matrix is symmetric)
        for (int b = 0; b < 3; ++b) {
            const double* col = values + outer[3 * I + b];
            for (int k = first; k < last; ++k)
                for (int a = 0; a < 3; ++a)
                    m_node_value[9 * std::size_t(k) + 3 * std::size_t(b) + std::size_t(a)]
                        = col[3 * (k - first) + a];
        }
        double d[9];
        std::copy_n(m_node_value.data() + 9 * std::size_t(m_node_diagonal[std::size_t(I)]), 9, d);
        if (hybrid) {
            // l1 term: each row's absolute sum over other threads' columns
            for (int k = first; k < last; ++k) {
                if (k >= m_node_own_begin[std::size_t(I)] && k < m_node_own_end[std::size_t(I)])
                    continue;
                for (int b = 0; b < 3; ++b)
                    for (int a = 0; a < 3; ++a)
                        m_fine_l1[3 * I + b]
                            += std::abs(m_node_value[9 * std::size_t(k) + 3 * b + a]);
            }
            for (int b = 0; b < 3; ++b)
                d[4 * b] += m_fine_l1[3 * I + b];
        }
        ok = invert_spd3(d, m_node_inverse.data() + 9 * I) && ok;
    }
    return ok;
}

void AmgCycle::fine_down_blocks(const double* b, double* x, double* r) const {
    const long nodes = long(m_node_diagonal.size());
    const double* value = m_node_value.data();
    const int* column = m_node_column.data();
    const double* inv = m_node_inverse.data();
    // forward block Gauss-Seidel from zero: the strict lower blocks only
    for (long I = 0; I < nodes; ++I) {
        double s[3] = { 0, 0, 0 };
        add_blocks(
            value, column, x, m_node_ptr[std::size_t(I)], m_node_diagonal[std::size_t(I)], s);
        const double u[3] = { b[3 * I] - s[0], b[3 * I + 1] - s[1], b[3 * I + 2] - s[2] };
        apply3(inv + 9 * I, u, x + 3 * I);
    }
    // r = b - A x = -(strict upper blocks) x
    for (long I = 0; I < nodes; ++I) {
        double s[3] = { 0, 0, 0 };
        add_blocks(value, column, x, m_node_diagonal[std::size_t(I)] + 1,
            m_node_ptr[std::size_t(I) + 1], s);
        for (int c = 0; c < 3; ++c)
            r[3 * I + c] = -s[c];
    }
}

void AmgCycle::fine_up_blocks(const double* b, double* x) const {
    const double* value = m_node_value.data();
    const int* column = m_node_column.data();
    const double* inv = m_node_inverse.data();
    for (long I = long(m_node_diagonal.size()) - 1; I >= 0; --I) {
        const int kd = m_node_diagonal[std::size_t(I)];
        double s[3] = { 0, 0, 0 };
        add_blocks(value, column, x, m_node_ptr[std::size_t(I)], kd, s);
        add_blocks(value, column, x, kd + 1, m_node_ptr[std::size_t(I) + 1], s);
        const double u[3] = { b[3 * I] - s[0], b[3 * I + 1] - s[1], b[3 * I + 2] - s[2] };
        apply3(inv + 9 * I, u, x + 3 * I);
    }
}

void AmgCycle::fine_down_blocks_hybrid(const double* b, double* x) {
    const int T = m_threads;
    const double* value = m_node_value.data();
    const int* column = m_node_column.data();
    const double* inv = m_node_inverse.data();
    const double* l1 = m_fine_l1.data();
    double* r = m_fine_residual.data();
#pragma omp parallel num_threads(T)
    {
        // forward l1 block Gauss-Seidel from zero inside each thread's nodes
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int I = m_block_rows[std::size_t(t)] / 3; I < m_block_rows[std::size_t(t) + 1] / 3;
                 ++I) {
                double s[3] = { 0, 0, 0 };
                add_blocks(value, column, x, m_node_own_begin[std::size_t(I)],
                    m_node_diagonal[std::size_t(I)], s);
                const double u[3] = { b[3 * I] - s[0], b[3 * I + 1] - s[1], b[3 * I + 2] - s[2] };
                apply3(inv + 9 * std::size_t(I), u, x + 3 * I);
            }
            // r = b - A x = l1 x - (strict upper blocks and other threads' lower blocks) x
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int I = m_block_rows[std::size_t(t)] / 3; I < m_block_rows[std::size_t(t) + 1] / 3;
                 ++I) {
                double s[3] = { 0, 0, 0 };
                add_blocks(value, column, x, m_node_diagonal[std::size_t(I)] + 1,
                    m_node_ptr[std::size_t(I) + 1], s);
                add_blocks(value, column, x, m_node_ptr[std::size_t(I)],
                    m_node_own_begin[std::size_t(I)], s);
                for (int c = 0; c < 3; ++c)
                    r[3 * I + c] = l1[3 * I + c] * x[3 * I + c] - s[c];
            }
    }
}

void AmgCycle::fine_up_blocks_hybrid(const double* b, double* x) {
    const int T = m_threads;
    const double* value = m_node_value.data();
    const int* column = m_node_column.data();
    const double* inv = m_node_inverse.data();
    double* cross = m_cross.data();
#pragma omp parallel num_threads(T)
    {
        // other threads' columns at their values before the sweep (Jacobi across threads)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int I = m_block_rows[std::size_t(t)] / 3; I < m_block_rows[std::size_t(t) + 1] / 3;
                 ++I) {
                double s[3] = { 0, 0, 0 };
                add_blocks(value, column, x, m_node_ptr[std::size_t(I)],
                    m_node_own_begin[std::size_t(I)], s);
                add_blocks(value, column, x, m_node_own_end[std::size_t(I)],
                    m_node_ptr[std::size_t(I) + 1], s);
                for (int c = 0; c < 3; ++c)
                    cross[3 * I + c] = s[c];
            }
            // backward l1 block Gauss-Seidel inside each thread's nodes, the adjoint of the
            // forward sweep: x_I += (D_I + l1_I)^-1 (b - A x)_I
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int I = m_block_rows[std::size_t(t) + 1] / 3 - 1;
                 I >= m_block_rows[std::size_t(t)] / 3; --I) {
                double s[3] = { 0, 0, 0 };
                add_blocks(value, column, x, m_node_own_begin[std::size_t(I)],
                    m_node_own_end[std::size_t(I)], s);
                const double u[3]
                    = { b[3 * I] - cross[3 * I] - s[0], b[3 * I + 1] - cross[3 * I + 1] - s[1],
                          b[3 * I + 2] - cross[3 * I + 2] - s[2] };
                double dx[3];
                apply3(inv + 9 * std::size_t(I), u, dx);
                for (int c = 0; c < 3; ++c)
                    x[3 * I + c] += dx[c];
            }
    }
}

} // namespace polycut::solve::detail
