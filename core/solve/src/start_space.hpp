// The start of a PCG solve projected onto the span of earlier solutions: a Galerkin projection
// (Fischer 1998, "Projection techniques for iterative solution of Ax = b with successive
// right-hand sides", Comput. Methods Appl. Mech. Engrg. 163). A time step's solutions (the
// velocity increments dv) follow the few slow modes of the body, so the best combination of the
// last few in the A-norm is a better start than a fixed rule (the last dv, or its linear
// extrapolation 2 dv_{n-1} - dv_{n-2}: both in the span).
//
// A changes from step to step (corotation), so an exact projection needs A s_i again for every
// kept s_i: k products with A per solve. Here each s_i keeps the product of its own solve
// instead, A_i s_i = b_i - r_i (PCG's residual at exit, free), and the small Galerkin matrix
// G_ij = (s_i.A_j s_j + s_j.A_i s_i) / 2 changes by one row per solve. On the sagging organ the
// lagged products gave the exact projection's iterations (167 against 165 over 160 steps, 270
// with the extrapolated start) for none of its 4 extra products (docs/perf.md). A start that
// the lag makes worse than zero is caught by PCG's energy test.
#pragma once

#include "polycut/solve/sparse.hpp"

#include <Eigen/Core>
#include <vector>

namespace polycut::solve::detail {

class StartSpace {
public:
    /// Most solutions kept: the small matrices live on the stack (no allocation per solve).
    static constexpr int kMaxCapacity = 32;
    using Small
        = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCapacity, kMaxCapacity>;
    using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCapacity, 1>;

    /// Keeps the last `capacity` solutions (0 = off; at most kMaxCapacity).
    explicit StartSpace(int capacity = 0);

    /// Forgets the kept solutions (the preconditioner was set up anew, a step was rolled back).
    void clear();

    /// x <- sum c_i s_i over the kept solutions of x's size, with G c = (s_i.b)_i (pseudo-inverse
    /// for dependent s_i). Returns false (x unchanged) when none is kept. After remap() the
    /// products are those of A, computed here (k products with A, `threads` as PCG's).
    bool project(const SparseMatrix& A, const Vector& b, Vector& x, int threads);

    /// A cut renumbered the unknowns (RowRemap): the kept solutions follow, a new unknown taking
    /// the weighted values of its origins (0 without); their products are recomputed with the
    /// next system's matrix, as the cut changed it.
    void remap(const RowRemap& m);

    /// Keeps x, the solution of A x = b with residual r = b - A x, dropping the oldest.
    void push(const Vector& x, const Vector& b, const Vector& r);

private:
    int m_capacity = 0;
    std::vector<Vector> m_saved; ///< ring of the last solutions s_i
    std::vector<Vector> m_products; ///< A_i s_i of each one's own solve
    Small m_gram; ///< G, capacity x capacity, the first size() rows in use
    int m_next = 0; ///< slot of the next push
    bool m_stale = false; ///< products to recompute (remap())
    /// G_ij = G_ji = (s_i.w_j + s_j.w_i) / 2 from the kept solutions and products
    void set_gram(std::size_t i, std::size_t j);
};

} // namespace polycut::solve::detail
