// Private: a symmetric Gauss-Seidel V-cycle over an AMG hierarchy built elsewhere (hypre
// BoomerAMG's interpolations P_l and Galerkin operators A_l, copied out after its set-up), with
// the finest level on the CURRENT system matrix rather than the one of the set-up. Free of hypre.
//
// Per level l (n_l unknowns), from x = 0:
//   forward Gauss-Seidel  x_i = (b_i - sum_{j<i} a_ij x_j) / a_ii    (strict lower part only)
//   residual              r_i = -sum_{j>i} a_ij x_j                  (strict upper part only: the
//                         forward sweep left b_i - sum_{j<=i} a_ij x_j = 0)
//   coarse correction     x += P_l cycle(l + 1, P_l^T r)
//   backward Gauss-Seidel x_i = (b_i - sum_{j!=i} a_ij x_j) / a_ii, i = n_l - 1 .. 0
// and a dense Cholesky solve on the coarsest level. Down-sweep and residual together read A once
// (hypre's cycle reads it twice: a full sweep, then a residual SpMV). The cycle is a symmetric
// positive definite operator for any SPD coarse operators (forward and backward Gauss-Seidel are
// adjoint, each convergent for SPD A), so PCG's theory holds although the coarse operators lag
// behind the fine one.
//
// With T > 1 threads (set_threads) the finest level, and each coarse level of at least
// kHybridNonzeros entries, is split into T contiguous row blocks and smoothed by l1 hybrid
// Gauss-Seidel (as hypre's relax types 13/14; Baker, Falgout, Kolev & Yang 2011, SIAM J. Sci.
// Comput. 33: 2864-2887): Gauss-Seidel inside a block, Jacobi across blocks (entries in other
// blocks' columns use the values from before the sweep), and each row's diagonal grown by the
// absolute sum of its entries in other blocks' columns. Forward down and backward up stay adjoint
// (D_l1 + L_B and D_l1 + U_B = (D_l1 + L_B)^T, L_B the block-diagonal strict lower part), so the
// cycle stays symmetric, and the l1 term makes the smoother convergent for any SPD A (M + M^T - A
// >= D), so the cycle stays positive definite; plain hybrid Gauss-Seidel does not (it lost
// definiteness after cuts on the organ). On a mesh numbered for locality few rows cross blocks and
// the smoother is nearly the serial one. The result depends on T only; T = 1 is the serial cycle.
//
// Node blocks (amg_node_blocks.cpp). When the fine matrix's unknowns come as whole nodes (three
// consecutive rows with one pattern of 3x3 blocks: an elasticity matrix whose fixed DOFs are
// whole nodes), the finest level is smoothed by block Gauss-Seidel on a block-CSR copy of the
// matrix (refreshed once per solve, see matrix_changed()): each node's 3x3 diagonal block is
// solved (with its rows' l1 terms on the diagonal when T > 1). Forward and backward block sweeps
// are adjoint as the point sweeps are, so the cycle stays symmetric positive definite. The copy
// reads one column index per nine contiguous values and one x_J per three rows: the two sweeps
// take about half the time of the point sweeps over the CSR matrix on the 5k-node organ
// (docs/perf.md "Organ scale"), and a block smoother treats a node's three strongly coupled
// unknowns together. Other matrices keep the point sweeps.
#pragma once

#include "polycut/solve/sparse.hpp"

#include <Eigen/Cholesky>
#include <vector>

namespace polycut::solve::detail {

/// Compressed sparse rows, each row sorted by column, with the slot of its diagonal entry
/// (square operators only): row i holds columns < i in [ptr[i], diagonal[i]) and > i in
/// (diagonal[i], ptr[i + 1]).
struct SortedCsr {
    int rows = 0;
    std::vector<int> ptr; ///< rows + 1
    std::vector<int> diagonal; ///< rows (operators), empty (interpolations)
    std::vector<int> column;
    std::vector<double> value;
};

/// The V-cycle (see the file comment).
class AmgCycle {
public:
    /// Adds level l's operator (coarse levels only: l >= 1) from CSR arrays (rows x rows, any
    /// column order within a row) and the interpolation from level l - 1 (rows of level l - 1 x
    /// rows of level l). Returns false if a diagonal entry is missing or not positive.
    bool add_level(int rows, const int* A_ptr, const int* A_col, const double* A_val, int P_rows,
        const int* P_ptr, const int* P_col, const double* P_val);
    /// Finishes the set-up for a fine matrix with the pattern of A (n x n, symmetric, full
    /// storage, sorted columns): finds its diagonal slots and factors the coarsest operator.
    /// Returns false if a diagonal is missing or the coarsest operator is not SPD.
    bool finish(const SparseMatrix& A);
    /// The finest level's unknowns were renumbered by a cut: row r of the new matrix was row
    /// m.old_of[r] of the old one (-1: a new unknown). The interpolation to the finest level
    /// keeps each surviving row; a new unknown gets the weighted sum of its origins' rows
    /// (m.origin_*: a node a cut duplicated or created interpolates the coarse space like its
    /// uncut neighbours), or a zero row without origins (then only the finest level's smoothing
    /// reaches it); the next apply() prepares the finest level for the new matrix.
    /// False when there is no coarse level.
    bool remap(const RowRemap& m);
    /// z = B r, one V-cycle from zero with A as the finest operator (n x n like in finish();
    /// its values may have changed, a changed pattern is detected and its diagonal slots found
    /// again). r, z: n. False if A has a missing or non-positive diagonal entry.
    bool apply(const SparseMatrix& A, const Vector& r, Vector& z);
    /// The values of the matrix passed to the next apply() differ from the last one's (a new
    /// solve): the node-block copy is refreshed then. The pattern is checked by apply() itself.
    void matrix_changed() {
        m_blocks_stale = true;
        ++m_solves_since_remap;
    }
    /// Smooth the finest level by node blocks when its matrix allows (see the file comment);
    /// takes effect at the next finish().
    void set_node_blocks(bool on) { m_node_blocks_wanted = on; }
    /// Threads for the finest level (>= 1, see the file comment); takes effect at once.
    void set_threads(int threads);
    /// Levels including the finest (0 before finish()).
    int levels() const { return m_ready ? int(m_levels.size()) + 1 : 0; }
    /// Levels smoothed on m_threads > 1 threads (hybrid Gauss-Seidel), the finest included.
    int threaded_levels() const;
    /// Unknowns of the fine matrix the cycle was finished for (-1 before finish()).
    long size() const { return m_ready ? m_fine_rows : -1; }
    void clear();

private:
    struct Level {
        SortedCsr A; ///< operator of this level (unused on level 0: the current matrix is used)
        SortedCsr P; ///< interpolation from this level to the finer one (rows of the finer one)
        Vector inverse_diagonal; ///< 1 / a_ii (n_l)
        Vector b, x, r; ///< right-hand side, iterate, residual (n_l)
        SortedCsr PT; ///< P^T, made when the restriction runs on threads (rows -1: stale)
        /// T > 1 and at least kHybridNonzeros entries: hybrid Gauss-Seidel as on the finest
        /// level, T row blocks of whole nodes (prepare_hybrid; empty: not prepared)
        std::vector<int> block_rows, own_begin, own_end;
        Vector l1, hybrid_inverse, cross; ///< l1 terms, 1 / (a_ii + l1_i), cross sums
    };
    /// Coarse operators with fewer entries are smoothed serially (a parallel region costs a few
    /// microseconds; the 5k organ's first coarse level has ~160k entries, its last ones < 10k).
    static constexpr std::size_t kHybridNonzeros = 20000;
    /// Prepares the level's hybrid blocks for m_threads; false if it is smoothed serially.
    bool prepare_hybrid(Level& level) const;
    void cycle(std::size_t l, const double* b, double* x);
    /// The finest level's down-sweep, residual and (after the coarse correction) up-sweep with
    /// m_threads row blocks (hybrid Gauss-Seidel).
    void fine_down_hybrid(const double* b, double* x);
    void fine_up_hybrid(const double* b, double* x);
    /// Per fine row, the slots of its own block's columns [m_block_begin, m_block_end).
    void find_block_slots();
    /// Node blocks (see the file comment): the block-CSR pattern of A if its unknowns come as
    /// whole nodes (true), else an empty one (false).
    bool find_node_blocks(const SparseMatrix& A);
    /// Node blocks of the thread ranges (m_block_rows): own-range block positions per node.
    void find_node_block_ranges();
    /// Copies A's values into the blocks, and the inverse diagonal blocks (with the l1 terms for
    /// T > 1); false if a diagonal block is not positive definite.
    bool refresh_node_blocks(const SparseMatrix& A);
    void fine_down_blocks(const double* b, double* x, double* r) const;
    void fine_up_blocks(const double* b, double* x) const;
    void fine_down_blocks_hybrid(const double* b, double* x);
    void fine_up_blocks_hybrid(const double* b, double* x);

    std::vector<Level> m_levels; ///< coarse levels 1 .. L-1 (index l - 1)
    // finest level: slots of the current matrix
    long m_fine_rows = -1;
    long m_fine_nonzeros = -1;
    std::vector<int> m_fine_diagonal; ///< value slot of each diagonal entry of A
    Vector m_fine_residual;
    /// of the current matrix (with the l1 terms for T > 1), refreshed once per solve
    Vector m_fine_inverse_diagonal;
    const SparseMatrix* m_A = nullptr; ///< the matrix of the running apply()
    SparseMatrix m_compressed; ///< apply() on an uncompressed matrix: its compressed copy
    Eigen::LLT<Eigen::MatrixXd> m_coarsest;
    bool m_coarsest_factored = false; ///< m_coarsest holds the coarsest coarse level's factor
    /// Solves begun since the last remap(): the finest level's P^T is made again only from the
    /// second one on. While a blade cuts, every tick remaps, and a transpose per tick (~1.2 ms
    /// on the split organ) cost more than the serial restriction of that tick's few iterations.
    long m_solves_since_remap = 2;
    bool m_ready = false;
    int m_threads = 1;
    /// remap(): per coarse unknown, its entry in the new row being summed (-1: none)
    std::vector<int> m_remap_slot;
    std::vector<int> m_block_rows; ///< T + 1 row bounds of the fine blocks
    std::vector<int> m_block_begin, m_block_end; ///< fine rows: own-block column slots
    Vector m_cross; ///< fine rows: sum over other blocks' columns before the up-sweep
    Vector m_fine_l1; ///< fine rows: sum of |a_ij| over other blocks' columns (l1 smoothing)
    /// Node blocks: block-CSR of the fine matrix (nodes rows, empty: point sweeps). Row I holds
    /// blocks [m_node_ptr[I], m_node_ptr[I + 1]) with first columns m_node_column (3 J), values
    /// 9 per block (row-major), its diagonal block at m_node_diagonal[I]; m_node_inverse: the
    /// inverse diagonal blocks (9 per node); m_node_own_begin/end: per node the blocks in its
    /// thread's columns (T > 1).
    std::vector<int> m_node_ptr, m_node_column, m_node_diagonal;
    std::vector<int> m_node_own_begin, m_node_own_end;
    std::vector<double> m_node_value, m_node_inverse;
    bool m_blocks_stale = true;
    bool m_node_blocks_wanted = false;
};

} // namespace polycut::solve::detail
