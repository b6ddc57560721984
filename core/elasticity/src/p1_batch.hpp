// Batched corotated P1 kernel: the closed-form tet kernel of elastic_model.cpp evaluated for
// kP1Lanes tets at once in structure-of-arrays form (GCC vector extensions), so the rotation
// extraction and the stiffness blocks use full SIMD width. Internal to polycut_elasticity.
#pragma once

#include "polycut/common/types.hpp"

namespace polycut::elasticity::detail {

/// Tets per batch.
inline constexpr int kP1Lanes = 4;

/// One P1 tet's cached data, as views into ElasticModel's per-cell tables.
struct P1TetView {
    const Index* nodes; ///< 4 node ids
    const double (*g)[3]; ///< P1 gradients g_i [1/m] (4 x 3)
    const double (*c0)[3]; ///< sum_j (X_j - X_c) g_j^T (3 x 3, the identity up to round-off)
    double volume; ///< [m^3]
    Mat3* rotation; ///< warm start in, polar rotation of F out (corotated only)
    const int* scatter; ///< 12 x 12 value slots of the reduced stiffness (-1: fixed)
    /// Compact form when all 12 DOFs are free (else null): [4 * i + j] = slot of entry (3i, 3j),
    /// [16 + j] = length of node j's columns; entry (3i + a, 3j + b) is at
    /// block[4 i + j] + b block[16 + j] + a (rows of a node are consecutive in a column, and the
    /// three columns of a node share their row structure).
    const int* block;
};

/// The step matrix's stiffness part assembled directly (ElasticModel::assemble_step): the
/// blocks go into the values scaled by `scale`, and kv (3#N) gets the scaled blocks times v
/// (3#N, row-major, the same node order as x).
struct StepProduct {
    double scale = 1; ///< factor on every stiffness block written
    const double* v = nullptr; ///< velocities [m/s] (3#N)
    double* kv = nullptr; ///< += scale K v (3#N)
};

/// Evaluates `count` (1..kP1Lanes) tets: forces into f_int (3#N, may be null), stiffness blocks
/// into K's values (may be null), with x the world positions (#N x 3, row-major) [m]. Per tet
/// the same quantities as the scalar kernel (000 eq. 10-11 corotated, H = R^T F - C0, sigma =
/// lambda tr(H) I + mu (H + H^T), f_i = -V R sigma g_i, blocks V (lambda r_i r_j^T + mu r_j r_i^T
/// + mu g_i.g_j I)); equal to it up to round-off. A tet whose rotation the vectorized warm
/// Newton iteration does not settle in 3 steps (large rotation since the last call, a nearly
/// flat or inverted tet) takes the scalar polar_rotation_warm() path.
/// With `step` (may be null), the blocks are scaled and their product with v accumulated (see
/// StepProduct).
void p1_batch(const P1TetView* tets, int count, double lambda, double mu, const double* x,
    bool corotated, double* Kvals, double* fint, const StepProduct* step = nullptr);

} // namespace polycut::elasticity::detail
