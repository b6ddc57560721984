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

/// T row blocks of a level for hybrid Gauss-Seidel: block t is rows [rows[t], rows[t + 1]),
/// and row i's entries in its own block's columns are the slots [begin[i], end[i]).
struct Blocks {
    int T;
    const int* rows;
    const int* begin;
    const int* end;
};

/// Per row of a sorted CSR operator, the slots of its own block's columns.
void find_own_slots(const int* ptr, const int* column, const std::vector<int>& rows,
    std::vector<int>& begin, std::vector<int>& end) {
    const std::size_t T = rows.size() - 1;
    begin.resize(std::size_t(rows.back()));
    end.resize(std::size_t(rows.back()));
    for (std::size_t t = 0; t < T; ++t) {
        const int lo = rows[t], hi = rows[t + 1];
        for (int i = lo; i < hi; ++i) {
            const int* first = column + ptr[i];
            const int* last = column + ptr[i + 1];
            begin[std::size_t(i)] = int(std::lower_bound(first, last, lo) - column);
            end[std::size_t(i)] = int(std::lower_bound(first, last, hi) - column);
        }
    }
}

/// The l1 terms (sum of |a_ij| over other blocks' columns) and 1 / (a_ii + l1_i) per row, each
/// block's rows on its own thread (rows are independent: the result does not depend on it).
void l1_terms(const View& a, const Blocks& k, double* l1, double* inverse) {
#pragma omp parallel for num_threads(k.T) schedule(static, 1) if (k.T > 1)
    for (int t = 0; t < k.T; ++t)
        for (int i = k.rows[t]; i < k.rows[t + 1]; ++i) {
            double s = 0;
            for (int q = a.ptr[i]; q < k.begin[i]; ++q)
                s += std::abs(a.value[q]);
            for (int q = k.end[i]; q < a.ptr[i + 1]; ++q)
                s += std::abs(a.value[q]);
            l1[i] = s;
            inverse[i] = 1.0 / (a.value[a.diagonal[i]] + s);
        }
}

/// Hybrid down-sweep from x = 0 and its residual: forward l1 Gauss-Seidel inside each block
/// (a.inverse_diagonal holds 1 / (a_ii + l1_i)), then r = b - A x.
void hybrid_down(
    const View& a, const Blocks& k, const double* l1, const double* b, double* x, double* r) {
#pragma omp parallel num_threads(k.T)
    {
        // forward l1 Gauss-Seidel from zero inside each block (other blocks' x are still 0)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < k.T; ++t)
            for (int i = k.rows[t]; i < k.rows[t + 1]; ++i)
                x[i] = (b[i] - row_dot(a.value, a.column, x, k.begin[i], a.diagonal[i]))
                    * a.inverse_diagonal[i];
                // r = b - A x = (D_l1 + L_B) x - A x: the l1 term, minus what the sweep did not use
                // (the strict upper part and the other blocks' lower columns)
#pragma omp for schedule(static, 1)
        for (int t = 0; t < k.T; ++t)
            for (int i = k.rows[t]; i < k.rows[t + 1]; ++i)
                r[i] = l1[i] * x[i]
                    - (row_dot(a.value, a.column, x, a.diagonal[i] + 1, a.ptr[i + 1])
                        + row_dot(a.value, a.column, x, a.ptr[i], k.begin[i]));
    }
}

/// Hybrid up-sweep, the adjoint of hybrid_down(): other blocks' columns at their values from
/// before the sweep (Jacobi across blocks, kept in `cross`), backward l1 Gauss-Seidel inside.
void hybrid_up(const View& a, const Blocks& k, double* cross, const double* b, double* x) {
#pragma omp parallel num_threads(k.T)
    {
#pragma omp for schedule(static, 1)
        for (int t = 0; t < k.T; ++t)
            for (int i = k.rows[t]; i < k.rows[t + 1]; ++i)
                cross[i] = row_dot(a.value, a.column, x, a.ptr[i], k.begin[i])
                    + row_dot(a.value, a.column, x, k.end[i], a.ptr[i + 1]);
                // x_i += (b - A x)_i / (a_ii + l1_i), i descending
#pragma omp for schedule(static, 1)
        for (int t = 0; t < k.T; ++t)
            for (int i = k.rows[t + 1] - 1; i >= k.rows[t]; --i) {
                const double lower = row_dot(a.value, a.column, x, k.begin[i], a.diagonal[i]);
                const double upper = row_dot(a.value, a.column, x, a.diagonal[i] + 1, k.end[i]);
                x[i] += (b[i] - cross[i] - lower - upper - a.value[a.diagonal[i]] * x[i])
                    * a.inverse_diagonal[i];
            }
    }
}

/// T = rows.size() - 1 contiguous blocks of whole units (rows of a node) over n rows.
std::vector<int> block_bounds(int n, int T, int unit) {
    std::vector<int> rows(std::size_t(T) + 1, n);
    for (int t = 0; t < T; ++t)
        rows[std::size_t(t)] = int(unit * (long(n) / unit * t / T));
    return rows;
}

/// Q = P^T (P: n_fine x n_coarse, sorted or not), rows sorted by column.
void transpose(const SortedCsr& P, int coarse_rows, SortedCsr& Q) {
    Q.rows = coarse_rows;
    Q.ptr.assign(std::size_t(coarse_rows) + 1, 0);
    for (int c : P.column)
        ++Q.ptr[std::size_t(c) + 1];
    for (std::size_t j = 0; j < std::size_t(coarse_rows); ++j)
        Q.ptr[j + 1] += Q.ptr[j];
    Q.column.resize(P.column.size());
    Q.value.resize(P.value.size());
    std::vector<int> next(Q.ptr.begin(), Q.ptr.end() - 1);
    for (int i = 0; i < P.rows; ++i)
        for (int k = P.ptr[std::size_t(i)]; k < P.ptr[std::size_t(i) + 1]; ++k) {
            const int slot = next[std::size_t(P.column[std::size_t(k)])]++;
            Q.column[std::size_t(slot)] = i;
            Q.value[std::size_t(slot)] = P.value[std::size_t(k)];
        }
}

} // namespace

bool AmgCycle::add_level(int rows, const int* A_ptr, const int* A_col, const double* A_val,
    int P_rows, const int* P_ptr, const int* P_col, const double* P_val) {
    m_ready = false;
    m_coarsest_factored = false;
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
    // the coarsest operator (the fine matrix itself when there is no coarse level); a coarse
    // one is factored once per set-up, not again when a cut changes the fine pattern (the
    // organ scenes' 366 x 366 factor costs milliseconds)
    if (!m_levels.empty() && m_coarsest_factored) {
        m_ready = true;
        return true;
    }
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
    m_coarsest_factored = !m_levels.empty();
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
    // coarse levels of at least kHybridNonzeros entries are smoothed by T threads too
    Level* own = l == 0 ? nullptr : &m_levels[l - 1];
    const bool coarse_hybrid = own && m_threads > 1 && prepare_hybrid(*own);
    const bool hybrid = (l == 0 && m_threads > 1) || coarse_hybrid;
    const bool blocks = l == 0 && !m_node_ptr.empty();
    if (coarse_hybrid) {
        a.inverse_diagonal = own->hybrid_inverse.data();
        hybrid_down(a,
            { m_threads, own->block_rows.data(), own->own_begin.data(), own->own_end.data() },
            own->l1.data(), b, x, r);
    } else if (hybrid && blocks)
        fine_down_blocks_hybrid(b, x);
    else if (hybrid)
        fine_down_hybrid(b, x);
    else if (blocks)
        fine_down_blocks(b, x, r);
    else {
        forward_from_zero(a, b, x);
        upper_residual(a, x, r);
    }
    // restrict to the next level: b_c = P^T r (P: rows of this level x rows of the next), by
    // rows of P^T on T threads (each b_c entry summed in one order whatever T)
    Level& next = m_levels[l];
    const SortedCsr& P = next.P;
    double* bc = next.b.data();
    // (the finest level's P^T only once the interpolation has stayed for a solve, see
    // m_solves_since_remap)
    const bool transposed = next.PT.rows == next.A.rows || l > 0 || m_solves_since_remap >= 2;
    if (hybrid && transposed) {
        if (next.PT.rows != next.A.rows)
            transpose(P, next.A.rows, next.PT);
        const SortedCsr& Q = next.PT;
#pragma omp parallel for num_threads(m_threads) schedule(static)
        for (int j = 0; j < Q.rows; ++j)
            bc[j] = row_dot(Q.value.data(), Q.column.data(), r, Q.ptr[std::size_t(j)],
                Q.ptr[std::size_t(j) + 1]);
    } else {
        next.b.setZero();
        for (int i = 0; i < P.rows; ++i) {
            const double ri = r[i];
            for (int k = P.ptr[std::size_t(i)]; k < P.ptr[std::size_t(i) + 1]; ++k)
                bc[P.column[std::size_t(k)]] += P.value[std::size_t(k)] * ri;
        }
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
    if (coarse_hybrid)
        hybrid_up(a,
            { m_threads, own->block_rows.data(), own->own_begin.data(), own->own_end.data() },
            own->cross.data(), b, x);
    else if (hybrid && blocks)
        fine_up_blocks_hybrid(b, x);
    else if (hybrid)
        fine_up_hybrid(b, x);
    else if (blocks)
        fine_up_blocks(b, x);
    else
        backward(a, b, x);
}

int AmgCycle::threaded_levels() const {
    if (!m_ready || m_threads <= 1)
        return 0;
    return 1 + int(std::count_if(m_levels.begin(), m_levels.end(), [](const Level& level) {
        return level.A.value.size() >= kHybridNonzeros;
    }));
}

bool AmgCycle::prepare_hybrid(Level& level) const {
    const SortedCsr& A = level.A;
    if (A.value.size() < kHybridNonzeros)
        return false;
    if (level.block_rows.size() == std::size_t(m_threads) + 1)
        return true;
    // whole nodes per block when the level's unknowns come in threes (systems AMG keeps a
    // node's unknowns together on every level)
    level.block_rows = block_bounds(A.rows, m_threads, A.rows % 3 == 0 ? 3 : 1);
    find_own_slots(A.ptr.data(), A.column.data(), level.block_rows, level.own_begin, level.own_end);
    level.l1.resize(A.rows);
    level.hybrid_inverse.resize(A.rows);
    level.cross.resize(A.rows);
    l1_terms(view(A, level.inverse_diagonal),
        { m_threads, level.block_rows.data(), level.own_begin.data(), level.own_end.data() },
        level.l1.data(), level.hybrid_inverse.data());
    return true;
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
    if (m_blocks_stale) { // once per solve: the values are those of the whole solve
        const double* values = matrix->valuePtr();
        if (m_threads > 1)
            // l1 hybrid Gauss-Seidel: a row's diagonal grows by the absolute sum of its entries
            // in other blocks' columns, so M + M^T - A >= D (M = D_l1 + L_B) and the smoother
            // converges for any SPD A (Baker, Falgout, Kolev & Yang 2011); without it the cycle
            // stopped being positive definite after cuts on the organ.
            l1_terms({ int(m_fine_rows), matrix->outerIndexPtr(), m_fine_diagonal.data(),
                         matrix->innerIndexPtr(), values, nullptr },
                { m_threads, m_block_rows.data(), m_block_begin.data(), m_block_end.data() },
                m_fine_l1.data(), m_fine_inverse_diagonal.data());
        else
            for (long i = 0; i < m_fine_rows; ++i)
                m_fine_inverse_diagonal[i] = 1.0 / values[m_fine_diagonal[std::size_t(i)]];
        m_blocks_stale = false;
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
    // The old rows from `kept` on are set aside (none when the cut only appended unknowns) and P
    // is cut back to its kept rows, which stay where they are: no copy of the whole
    // interpolation per cut. Old row o is then P's row o below `kept`, else the set-aside one.
    const int old_rows = P.rows;
    const int tail_at = P.ptr[kept];
    const std::vector<int> tail_ptr(P.ptr.begin() + std::ptrdiff_t(kept), P.ptr.end());
    const std::vector<int> tail_column(P.column.begin() + tail_at, P.column.end());
    const std::vector<double> tail_value(P.value.begin() + tail_at, P.value.end());
    P.ptr.resize(kept + 1);
    P.column.resize(std::size_t(tail_at));
    P.value.resize(std::size_t(tail_at));
    const auto old_row = [&](long o, auto&& visit) {
        if (std::size_t(o) < kept) {
            for (int k = P.ptr[std::size_t(o)]; k < P.ptr[std::size_t(o) + 1]; ++k)
                visit(P.column[std::size_t(k)], P.value[std::size_t(k)]);
            return;
        }
        const std::size_t t = std::size_t(o) - kept;
        for (int k = tail_ptr[t] - tail_at; k < tail_ptr[t + 1] - tail_at; ++k)
            visit(tail_column[std::size_t(k)], tail_value[std::size_t(k)]);
    };
    // A new unknown's row: its origins' rows summed by column in a dense accumulator over the
    // coarse unknowns (slot[c] the entry of column c in `row`, -1 if none), then sorted by
    // column (a sort of all the origins' entries was ~2 % of a split stroke's time).
    const int coarse = m_levels.front().A.rows;
    if (m_remap_slot.size() != std::size_t(coarse))
        m_remap_slot.assign(std::size_t(coarse), -1);
    std::vector<std::pair<int, double>> row;
    for (std::size_t r = kept; r < old_of.size(); ++r) {
        const long o = old_of[r];
        if (o >= 0 && o < old_rows) {
            old_row(o, [&](int column, double value) {
                P.column.push_back(column);
                P.value.push_back(value);
            });
        } else if (o < 0 && origins) {
            row.clear();
            for (int j = m.origin_ptr[r]; j < m.origin_ptr[r + 1]; ++j) {
                const long from = m.origin_row[std::size_t(j)];
                if (from < 0 || from >= old_rows)
                    continue;
                const double w = m.origin_weight[std::size_t(j)];
                old_row(from, [&](int column, double value) {
                    int& at = m_remap_slot[std::size_t(column)];
                    if (at < 0) {
                        at = int(row.size());
                        row.emplace_back(column, w * value);
                    } else {
                        row[std::size_t(at)].second += w * value;
                    }
                });
            }
            std::sort(row.begin(), row.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
            for (const auto& [column, value] : row) {
                m_remap_slot[std::size_t(column)] = -1;
                P.column.push_back(column);
                P.value.push_back(value);
            }
        }
        P.ptr.push_back(int(P.column.size()));
    }
    P.rows = int(old_of.size());
    m_levels.front().PT.rows = -1; // transposed again, from the second solve on
    m_solves_since_remap = 0;
    m_ready = false; // apply() runs finish() on the new matrix
    m_fine_rows = -1;
    m_block_rows.clear();
    return true;
}

void AmgCycle::set_threads(int threads) {
    m_threads = std::max(threads, 1);
    m_block_rows.clear(); // the blocks are found again by the next apply()
    for (Level& level : m_levels)
        level.block_rows.clear();
}

void AmgCycle::find_block_slots() {
    const int n = int(m_fine_rows);
    // node blocks: whole nodes per thread
    m_block_rows = block_bounds(n, m_threads, m_node_ptr.empty() ? 1 : 3);
    m_cross.setZero(n);
    m_fine_l1.setZero(n);
    find_own_slots(
        m_A->outerIndexPtr(), m_A->innerIndexPtr(), m_block_rows, m_block_begin, m_block_end);
    m_blocks_stale = true; // the l1 terms (and node blocks) follow the blocks
    find_node_block_ranges();
}

void AmgCycle::fine_down_hybrid(const double* b, double* x) {
    const View a { int(m_fine_rows), m_A->outerIndexPtr(), m_fine_diagonal.data(),
        m_A->innerIndexPtr(), m_A->valuePtr(), m_fine_inverse_diagonal.data() };
    hybrid_down(a, { m_threads, m_block_rows.data(), m_block_begin.data(), m_block_end.data() },
        m_fine_l1.data(), b, x, m_fine_residual.data());
}

void AmgCycle::fine_up_hybrid(const double* b, double* x) {
    const View a { int(m_fine_rows), m_A->outerIndexPtr(), m_fine_diagonal.data(),
        m_A->innerIndexPtr(), m_A->valuePtr(), m_fine_inverse_diagonal.data() };
    hybrid_up(a, { m_threads, m_block_rows.data(), m_block_begin.data(), m_block_end.data() },
        m_cross.data(), b, x);
}

void AmgCycle::clear() {
    m_levels.clear();
    m_coarsest_factored = false;
    m_node_ptr.clear();
    m_blocks_stale = true;
    m_fine_rows = m_fine_nonzeros = -1;
    m_fine_diagonal.clear();
    m_ready = false;
}

} // namespace polycut::solve::detail
