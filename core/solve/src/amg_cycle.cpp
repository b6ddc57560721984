// Symmetric Gauss-Seidel V-cycle over a copied AMG hierarchy (see amg_cycle.hpp).
#include "amg_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace polycut::solve::detail {

namespace {

/// sum_k a[k] x[column[k]] over [begin, end) with two accumulators (two dependency chains; the
/// sweeps and SpMVs here are bound by the latency of the additions, not by bandwidth, while A
/// fits in the cache).
inline double row_dot(const double* a, const int* column, const double* x, int begin, int end) {
    double even = 0, odd = 0;
    int k = begin;
    for (; k + 1 < end; k += 2) {
        even += a[k] * x[column[k]];
        odd += a[k + 1] * x[column[k + 1]];
    }
    if (k < end)
        even += a[k] * x[column[k]];
    return even + odd;
}

/// Rows of a square operator: CSR arrays, diagonal slots and inverse diagonal entries.
struct View {
    int rows;
    const int* ptr;
    const int* diagonal;
    const int* column;
    const double* value;
    const double* inverse_diagonal;
};

/// x = forward Gauss-Seidel sweep from x = 0: only the strict lower part is read.
void forward_from_zero(const View& a, const double* b, double* x) {
    for (int i = 0; i < a.rows; ++i) {
        const double s = b[i] - row_dot(a.value, a.column, x, a.ptr[i], a.diagonal[i]);
        x[i] = s * a.inverse_diagonal[i]; // no division in the dependency chain
    }
}

/// r = b - A x after forward_from_zero(): -(strict upper part) x.
void upper_residual(const View& a, const double* x, double* r) {
    for (int i = 0; i < a.rows; ++i)
        r[i] = -row_dot(a.value, a.column, x, a.diagonal[i] + 1, a.ptr[i + 1]);
}

/// One backward Gauss-Seidel sweep on x (the adjoint of the forward sweep).
void backward(const View& a, const double* b, double* x) {
    for (int i = a.rows - 1; i >= 0; --i) {
        const double lower = row_dot(a.value, a.column, x, a.ptr[i], a.diagonal[i]);
        const double upper = row_dot(a.value, a.column, x, a.diagonal[i] + 1, a.ptr[i + 1]);
        x[i] = (b[i] - lower - upper) * a.inverse_diagonal[i];
    }
}

View view(const SortedCsr& m, const Vector& inverse_diagonal) {
    return { m.rows, m.ptr.data(), m.diagonal.data(), m.column.data(), m.value.data(),
        inverse_diagonal.data() };
}

} // namespace

bool AmgCycle::add_level(int rows, const int* A_ptr, const int* A_col, const double* A_val,
    int P_rows, const int* P_ptr, const int* P_col, const double* P_val) {
    m_ready = false;
    Level level;
    SortedCsr& A = level.A;
    A.rows = rows;
    A.ptr.assign(A_ptr, A_ptr + rows + 1);
    const int nnz = A.ptr[std::size_t(rows)] - A.ptr[0];
    A.column.resize(std::size_t(nnz));
    A.value.resize(std::size_t(nnz));
    A.diagonal.assign(std::size_t(rows), -1);
    std::vector<int> order;
    const int base = A.ptr[0];
    for (int i = 0; i < rows; ++i) {
        const int begin = A_ptr[i], end = A_ptr[i + 1];
        order.resize(std::size_t(end - begin));
        std::iota(order.begin(), order.end(), begin);
        std::sort(order.begin(), order.end(), [&](int p, int q) { return A_col[p] < A_col[q]; });
        for (int k = begin; k < end; ++k) {
            const int from = order[std::size_t(k - begin)];
            A.column[std::size_t(k - base)] = A_col[from];
            A.value[std::size_t(k - base)] = A_val[from];
            if (A_col[from] == i)
                A.diagonal[std::size_t(i)] = k - base;
        }
    }
    for (int& p : A.ptr)
        p -= base;
    for (int i = 0; i < rows; ++i) {
        const int d = A.diagonal[std::size_t(i)];
        if (d < 0 || !(A.value[std::size_t(d)] > 0))
            return false;
    }
    SortedCsr& P = level.P;
    P.rows = P_rows;
    P.ptr.assign(P_ptr, P_ptr + P_rows + 1);
    const int p_base = P.ptr[0];
    for (int& p : P.ptr)
        p -= p_base;
    P.column.assign(P_col + p_base, P_col + P_ptr[P_rows]);
    P.value.assign(P_val + p_base, P_val + P_ptr[P_rows]);
    level.inverse_diagonal.resize(rows);
    for (int i = 0; i < rows; ++i)
        level.inverse_diagonal[i] = 1.0 / A.value[std::size_t(A.diagonal[std::size_t(i)])];
    level.b.setZero(rows);
    level.x.setZero(rows);
    level.r.setZero(rows);
    m_levels.push_back(std::move(level));
    return true;
}

bool AmgCycle::finish(const SparseMatrix& A) {
    m_ready = false;
    if (!A.isCompressed() || A.rows() != A.cols())
        return false;
    const long n = A.rows();
    m_fine_rows = n;
    m_fine_nonzeros = A.nonZeros();
    m_fine_diagonal.resize(std::size_t(n));
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    for (long j = 0; j < n; ++j) {
        const int* it = std::lower_bound(inner + outer[j], inner + outer[j + 1], int(j));
        if (it == inner + outer[j + 1] || *it != j || !(A.valuePtr()[it - inner] > 0))
            return false;
        m_fine_diagonal[std::size_t(j)] = int(it - inner);
    }
    m_fine_residual.setZero(n);
    m_fine_inverse_diagonal.setZero(n);
    m_A = &A;
    // before the thread blocks, which then fall on node bounds
    if (!m_node_blocks_wanted || !find_node_blocks(A))
        m_node_ptr.clear();
    find_block_slots();
    m_A = nullptr;
    // the coarsest operator (the fine matrix itself when there is no coarse level)
    Eigen::MatrixXd dense;
    if (m_levels.empty() && n > 4000)
        return false; // no hierarchy to speak of: let the caller use another cycle
    if (m_levels.empty()) {
        dense = Eigen::MatrixXd(A);
    } else {
        const SortedCsr& c = m_levels.back().A;
        dense.setZero(c.rows, c.rows);
        for (int i = 0; i < c.rows; ++i)
            for (int k = c.ptr[std::size_t(i)]; k < c.ptr[std::size_t(i) + 1]; ++k)
                dense(i, c.column[std::size_t(k)]) = c.value[std::size_t(k)];
        dense = 0.5 * (dense + dense.transpose()).eval(); // symmetric up to round-off
    }
    m_coarsest.compute(dense);
    if (m_coarsest.info() != Eigen::Success)
        return false;
    m_ready = true;
    return true;
}

void AmgCycle::cycle(std::size_t l, const double* b, double* x) {
    const std::size_t last = m_levels.size(); // index of the coarsest level
    if (l == last) {
        const int n = l == 0 ? int(m_fine_rows) : m_levels[l - 1].A.rows;
        Eigen::Map<const Vector> bv(b, n);
        Eigen::Map<Vector>(x, n) = m_coarsest.solve(bv);
        return;
    }
    View a;
    double* r = nullptr;
    if (l == 0) {
        a = { int(m_fine_rows), m_A->outerIndexPtr(), m_fine_diagonal.data(), m_A->innerIndexPtr(),
            m_A->valuePtr(), m_fine_inverse_diagonal.data() };
        r = m_fine_residual.data();
    } else {
        a = view(m_levels[l - 1].A, m_levels[l - 1].inverse_diagonal);
        r = m_levels[l - 1].r.data();
    }
    const bool hybrid = l == 0 && m_threads > 1;
    const bool blocks = l == 0 && !m_node_ptr.empty();
    if (hybrid && blocks)
        fine_down_blocks_hybrid(b, x);
    else if (hybrid)
        fine_down_hybrid(b, x);
    else if (blocks)
        fine_down_blocks(b, x, r);
    else {
        forward_from_zero(a, b, x);
        upper_residual(a, x, r);
    }
    // restrict to the next level: b_c = P^T r (P: rows of this level x rows of the next)
    Level& next = m_levels[l];
    const SortedCsr& P = next.P;
    next.b.setZero();
    double* bc = next.b.data();
    for (int i = 0; i < P.rows; ++i) {
        const double ri = r[i];
        for (int k = P.ptr[std::size_t(i)]; k < P.ptr[std::size_t(i) + 1]; ++k)
            bc[P.column[std::size_t(k)]] += P.value[std::size_t(k)] * ri;
    }
    cycle(l + 1, next.b.data(), next.x.data());
    const double* xc = next.x.data();
#pragma omp parallel for num_threads(m_threads) schedule(static) if (hybrid)
    for (int i = 0; i < P.rows; ++i) {
        double s = 0;
        for (int k = P.ptr[std::size_t(i)]; k < P.ptr[std::size_t(i) + 1]; ++k)
            s += P.value[std::size_t(k)] * xc[P.column[std::size_t(k)]];
        x[i] += s;
    }
    if (hybrid && blocks)
        fine_up_blocks_hybrid(b, x);
    else if (hybrid)
        fine_up_hybrid(b, x);
    else if (blocks)
        fine_up_blocks(b, x);
    else
        backward(a, b, x);
}

bool AmgCycle::apply(const SparseMatrix& A, const Vector& r, Vector& z) {
    z.resize(r.size());
    const SparseMatrix* matrix = &A;
    if (!A.isCompressed()) { // not on the hot path: the integrators' matrices are compressed
        m_compressed = A;
        m_compressed.makeCompressed();
        matrix = &m_compressed;
    }
    // same size, new pattern (the diagonal slots moved): find them again
    const auto slots_hold = [&] {
        const int* inner = matrix->innerIndexPtr();
        for (long i = 0; i < m_fine_rows; ++i)
            if (inner[m_fine_diagonal[std::size_t(i)]] != i)
                return false;
        return true;
    };
    if (!m_ready || matrix->nonZeros() != m_fine_nonzeros || matrix->rows() != m_fine_rows
        || !slots_hold())
        if (!finish(*matrix))
            return false;
    m_A = matrix;
    if (m_block_rows.size() != std::size_t(m_threads) + 1) {
        find_block_slots();
        m_blocks_stale = true;
    }
    if (!m_node_ptr.empty()) {
        if (m_blocks_stale && !refresh_node_blocks(*matrix)) {
            m_A = nullptr;
            return false;
        }
        m_blocks_stale = false;
        cycle(0, r.data(), z.data());
        m_A = nullptr;
        return true;
    }
    const double* values = matrix->valuePtr();
    for (long i = 0; i < m_fine_rows; ++i)
        m_fine_inverse_diagonal[i] = 1.0 / values[m_fine_diagonal[std::size_t(i)]];
    if (m_threads > 1) {
        // l1 hybrid Gauss-Seidel: a row's diagonal grows by the absolute sum of its entries in
        // other blocks' columns, so M + M^T - A >= D (M = D_l1 + L_B) and the smoother
        // converges for any SPD A (Baker, Falgout, Kolev & Yang 2011); without it the cycle
        // stopped being positive definite after cuts on the organ.
        const int* outer = matrix->outerIndexPtr();
        for (long i = 0; i < m_fine_rows; ++i) {
            double l1 = 0;
            for (int k = outer[i]; k < m_block_begin[std::size_t(i)]; ++k)
                l1 += std::abs(values[k]);
            for (int k = m_block_end[std::size_t(i)]; k < outer[i + 1]; ++k)
                l1 += std::abs(values[k]);
            m_fine_l1[i] = l1;
            if (l1 > 0)
                m_fine_inverse_diagonal[i] = 1.0 / (values[m_fine_diagonal[std::size_t(i)]] + l1);
        }
    }
    cycle(0, r.data(), z.data());
    m_A = nullptr;
    return true;
}

bool AmgCycle::remap(const RowRemap& m) {
    if (m_levels.empty())
        return false;
    SortedCsr& P = m_levels.front().P;
    const std::vector<long>& old_of = m.old_of;
    const bool origins = m.origin_ptr.size() == old_of.size() + 1;
    // Rows that kept their numbers (a cell-splitting cut appends its unknowns) stay in place:
    // only the rows from the first renumbered one on are made again.
    std::size_t kept = 0;
    while (kept < old_of.size() && kept < std::size_t(P.rows) && old_of[kept] == long(kept))
        ++kept;
    SortedCsr Q;
    Q.rows = int(old_of.size());
    Q.ptr.assign(P.ptr.begin(), P.ptr.begin() + std::ptrdiff_t(kept) + 1);
    Q.ptr.resize(old_of.size() + 1, 0);
    Q.column.assign(P.column.begin(), P.column.begin() + P.ptr[kept]);
    Q.value.assign(P.value.begin(), P.value.begin() + P.ptr[kept]);
    std::vector<std::pair<int, double>> row; // a new unknown's row, merged by column
    for (std::size_t r = kept; r < old_of.size(); ++r) {
        const long o = old_of[r];
        if (o >= 0 && o < P.rows) {
            for (int k = P.ptr[std::size_t(o)]; k < P.ptr[std::size_t(o) + 1]; ++k) {
                Q.column.push_back(P.column[std::size_t(k)]);
                Q.value.push_back(P.value[std::size_t(k)]);
            }
        } else if (o < 0 && origins) {
            row.clear();
            for (int j = m.origin_ptr[r]; j < m.origin_ptr[r + 1]; ++j) {
                const long from = m.origin_row[std::size_t(j)];
                if (from < 0 || from >= P.rows)
                    continue;
                const double w = m.origin_weight[std::size_t(j)];
                for (int k = P.ptr[std::size_t(from)]; k < P.ptr[std::size_t(from) + 1]; ++k)
                    row.emplace_back(P.column[std::size_t(k)], w * P.value[std::size_t(k)]);
            }
            std::sort(row.begin(), row.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
            for (const auto& [column, value] : row) {
                if (Q.ptr[r] < int(Q.column.size()) && Q.column.back() == column)
                    Q.value.back() += value;
                else {
                    Q.column.push_back(column);
                    Q.value.push_back(value);
                }
            }
        }
        Q.ptr[r + 1] = int(Q.column.size());
    }
    P = std::move(Q);
    m_ready = false; // apply() runs finish() on the new matrix
    m_fine_rows = -1;
    m_block_rows.clear();
    return true;
}

void AmgCycle::set_threads(int threads) {
    m_threads = std::max(threads, 1);
    m_block_rows.clear(); // the blocks are found again by the next apply()
}

void AmgCycle::find_block_slots() {
    const int n = int(m_fine_rows);
    const int T = m_threads;
    m_block_rows.assign(std::size_t(T) + 1, n);
    // node blocks: whole nodes per thread
    const long unit = m_node_ptr.empty() ? 1 : 3;
    for (int t = 0; t < T; ++t)
        m_block_rows[std::size_t(t)] = int(unit * (long(n) / unit * t / T));
    m_block_begin.resize(std::size_t(n));
    m_block_end.resize(std::size_t(n));
    m_cross.setZero(n);
    m_fine_l1.setZero(n);
    const int* outer = m_A->outerIndexPtr();
    const int* inner = m_A->innerIndexPtr();
    for (int t = 0; t < T; ++t) {
        const int lo = m_block_rows[std::size_t(t)], hi = m_block_rows[std::size_t(t) + 1];
        for (int i = lo; i < hi; ++i) {
            const int* begin = inner + outer[i];
            const int* end = inner + outer[i + 1];
            m_block_begin[std::size_t(i)] = int(std::lower_bound(begin, end, lo) - inner);
            m_block_end[std::size_t(i)] = int(std::lower_bound(begin, end, hi) - inner);
        }
    }
    find_node_block_ranges();
}

void AmgCycle::fine_down_hybrid(const double* b, double* x) {
    const int T = m_threads;
    const int* outer = m_A->outerIndexPtr();
    const int* inner = m_A->innerIndexPtr();
    const double* a = m_A->valuePtr();
    const double* inv = m_fine_inverse_diagonal.data();
    const double* l1 = m_fine_l1.data();
    const int* diag = m_fine_diagonal.data();
    double* r = m_fine_residual.data();
#pragma omp parallel num_threads(T)
    {
        // forward l1 Gauss-Seidel from zero inside each block (other blocks' x are still 0)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int i = m_block_rows[std::size_t(t)]; i < m_block_rows[std::size_t(t) + 1]; ++i)
                x[i] = (b[i] - row_dot(a, inner, x, m_block_begin[std::size_t(i)], diag[i]))
                    * inv[i];
                // r = b - A x = (D_l1 + L_B) x - A x: the l1 term, minus what the sweep did not use
                // (the strict upper part and the other blocks' lower columns)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int i = m_block_rows[std::size_t(t)]; i < m_block_rows[std::size_t(t) + 1]; ++i)
                r[i] = l1[i] * x[i]
                    - (row_dot(a, inner, x, diag[i] + 1, outer[i + 1])
                        + row_dot(a, inner, x, outer[i], m_block_begin[std::size_t(i)]));
    }
}

void AmgCycle::fine_up_hybrid(const double* b, double* x) {
    const int T = m_threads;
    const int* outer = m_A->outerIndexPtr();
    const int* inner = m_A->innerIndexPtr();
    const double* a = m_A->valuePtr();
    const double* inv = m_fine_inverse_diagonal.data();
    const int* diag = m_fine_diagonal.data();
    double* cross = m_cross.data();
#pragma omp parallel num_threads(T)
    {
        // other blocks' columns at their values before the sweep (Jacobi across blocks)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int i = m_block_rows[std::size_t(t)]; i < m_block_rows[std::size_t(t) + 1]; ++i)
                cross[i] = row_dot(a, inner, x, outer[i], m_block_begin[std::size_t(i)])
                    + row_dot(a, inner, x, m_block_end[std::size_t(i)], outer[i + 1]);
                // backward l1 Gauss-Seidel inside each block: x_i += (b - A x)_i / (a_ii + l1_i),
                // the adjoint of the forward sweep
#pragma omp for schedule(static, 1)
        for (int t = 0; t < T; ++t)
            for (int i = m_block_rows[std::size_t(t) + 1] - 1; i >= m_block_rows[std::size_t(t)];
                 --i) {
                const double lower = row_dot(a, inner, x, m_block_begin[std::size_t(i)], diag[i]);
                const double upper = row_dot(a, inner, x, diag[i] + 1, m_block_end[std::size_t(i)]);
                x[i] += (b[i] - cross[i] - lower - upper - a[diag[i]] * x[i]) * inv[i];
            }
    }
}

void AmgCycle::clear() {
    m_levels.clear();
    m_node_ptr.clear();
    m_blocks_stale = true;
    m_fine_rows = m_fine_nonzeros = -1;
    m_fine_diagonal.clear();
    m_ready = false;
}

} // namespace polycut::solve::detail
