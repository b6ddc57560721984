#include "p1_batch.hpp"

#include "polycut/elasticity/rotation.hpp"

#include <utility>

namespace polycut::elasticity::detail {
namespace {

// kP1Lanes doubles per vector; comparisons give kP1Lanes 64-bit masks (all ones = true). GCC
// lowers these to two SSE2 operations per vector on the baseline target and to one AVX2
// operation in the x86-64-v3 clone below.
typedef double vd __attribute__((vector_size(8 * kP1Lanes)));
typedef long long vm __attribute__((vector_size(8 * kP1Lanes)));

/// 3x3 matrices and 3-vectors of kP1Lanes lanes, [row][col].
struct M3 {
    vd m[3][3];
};
struct V3 {
    vd v[3];
};

[[gnu::always_inline]] inline void mul(const M3& a, const M3& b, M3& c) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
}

/// c = a^T b
[[gnu::always_inline]] inline void mul_tn(const M3& a, const M3& b, M3& c) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c.m[i][j] = a.m[0][i] * b.m[0][j] + a.m[1][i] * b.m[1][j] + a.m[2][i] * b.m[2][j];
}

[[gnu::always_inline]] inline void det(const M3& a, vd& d) {
    d = a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1])
        - a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0])
        + a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}

[[gnu::always_inline]] inline void identity(M3& a) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a.m[i][j] = vd {} + (i == j ? 1.0 : 0.0);
}

/// The warm Newton iteration of polar_rotation_warm() on the rotation itself, per lane (see
/// rotation.cpp): X = G^T F = (I + W) S, (tr S I - S) w = 2 axial(skew X), step Cayley(w / 2),
/// at most 3 steps. Lanes whose step falls below 1e-5 rad (remaining error ~1e-10) get R = G Q
/// and a set bit in `conv`; the others are left to the scalar path.
[[gnu::always_inline]] inline void warm_rotation(const M3& F, const M3& G, M3& R, vm& conv) {
    M3 Y;
    mul_tn(G, F, Y);
    vd scale2 = vd {};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            scale2 += Y.m[i][j] * Y.m[i][j];
    vd dx;
    det(Y, dx);
    // det X > 1e-6 |X|^3 without square roots (NaN compares false: scalar path).
    const vm ok = (scale2 > 0.0) & (dx > 0.0) & (dx * dx > 1e-12 * scale2 * scale2 * scale2);
    vm fail = ~ok;
    conv = vm {};
    // Ping-pong buffers instead of copies of the 3x3 products.
    M3 Qa, Qb, Yb;
    identity(Qa);
    M3 *Q = &Qa, *Qn = &Qb, *Yp = &Y, *Yn = &Yb;
    for (int it = 0; it < 3; ++it) {
        const M3& Yc = *Yp;
        const vd k0 = 0.5 * (Yc.m[2][1] - Yc.m[1][2]);
        const vd k1 = 0.5 * (Yc.m[0][2] - Yc.m[2][0]);
        const vd k2 = 0.5 * (Yc.m[1][0] - Yc.m[0][1]);
        // M = tr(S) I - S with S the symmetric part of Y.
        M3 M;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                M.m[i][j] = -0.5 * (Yc.m[i][j] + Yc.m[j][i]);
        const vd tr0 = M.m[0][0] + M.m[1][1] + M.m[2][2];
        for (int i = 0; i < 3; ++i)
            M.m[i][i] -= tr0;
        const vd tm = M.m[0][0] + M.m[1][1] + M.m[2][2];
        vd dm;
        det(M, dm);
        vm bad = ~(tm > 0.0) | ~(dm > 1e-9 * tm * tm * tm);
        // w = M^-1 (2 k) by the adjugate of the symmetric M.
        const vd a00 = M.m[1][1] * M.m[2][2] - M.m[1][2] * M.m[2][1];
        const vd a01 = M.m[0][2] * M.m[2][1] - M.m[0][1] * M.m[2][2];
        const vd a02 = M.m[0][1] * M.m[1][2] - M.m[0][2] * M.m[1][1];
        const vd a11 = M.m[0][0] * M.m[2][2] - M.m[0][2] * M.m[2][0];
        const vd a12 = M.m[0][2] * M.m[1][0] - M.m[0][0] * M.m[1][2];
        const vd a22 = M.m[0][0] * M.m[1][1] - M.m[0][1] * M.m[1][0];
        const vd s = 2.0 / dm;
        const vd w0 = s * (a00 * k0 + a01 * k1 + a02 * k2);
        const vd w1 = s * (a01 * k0 + a11 * k1 + a12 * k2);
        const vd w2 = s * (a02 * k0 + a12 * k1 + a22 * k2);
        const vd wn2 = w0 * w0 + w1 * w1 + w2 * w2;
        if (it == 0)
            bad |= ~(wn2 < 0.25); // warm start too far
        const vm live = ~(fail | conv);
        fail |= live & bad;
        const vm active = live & ~bad;
        // Cayley transform with c = w / 2 (identity on inactive lanes).
        const vd c0 = active ? 0.5 * w0 : vd {};
        const vd c1 = active ? 0.5 * w1 : vd {};
        const vd c2 = active ? 0.5 * w2 : vd {};
        M3 C;
        C.m[0][0] = vd {};
        C.m[0][1] = -c2;
        C.m[0][2] = c1;
        C.m[1][0] = c2;
        C.m[1][1] = vd {};
        C.m[1][2] = -c0;
        C.m[2][0] = -c1;
        C.m[2][1] = c0;
        C.m[2][2] = vd {};
        M3 C2, step;
        mul(C, C, C2);
        const vd f = 2.0 / (1.0 + c0 * c0 + c1 * c1 + c2 * c2);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                step.m[i][j] = (i == j ? 1.0 : 0.0) + f * (C.m[i][j] + C2.m[i][j]);
        mul(*Q, step, *Qn);
        std::swap(Q, Qn);
        mul_tn(step, Yc, *Yn);
        std::swap(Yp, Yn);
        conv |= active & (wn2 < 1e-10);
        fail |= active & ~(wn2 < 1e-10) & ~(wn2 < 1.0);
        const vm settled = conv | fail;
        bool all = true;
        for (int k = 0; k < kP1Lanes; ++k)
            all = all && settled[k] != 0;
        if (all)
            break;
    }
    mul(G, *Q, R);
}

} // namespace

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
void p1_batch(const P1TetView* tets, int count, double lambda, double mu, const double* x,
    bool corotated, double* Kvals, double* fint, const StepProduct* step) {
    constexpr int W = kP1Lanes;
    // Gather (lanes past count repeat the first tet; their results are dropped).
    V3 p[4], g[4];
    M3 C0, G;
    vd V;
    for (int k = 0; k < W; ++k) {
        const P1TetView& t = tets[k < count ? k : 0];
        for (int i = 0; i < 4; ++i)
            for (int a = 0; a < 3; ++a) {
                p[i].v[a][k] = x[3 * std::size_t(t.nodes[i]) + std::size_t(a)];
                g[i].v[a][k] = t.g[i][a];
            }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                C0.m[a][b][k] = t.c0[a][b];
                G.m[a][b][k] = corotated ? (*t.rotation)(a, b) : (a == b ? 1.0 : 0.0);
            }
        V[k] = t.volume;
    }
    // F = sum_i (p_i - x_c) g_i^T
    M3 F;
    for (int a = 0; a < 3; ++a) {
        const vd xc = 0.25 * (p[0].v[a] + p[1].v[a] + p[2].v[a] + p[3].v[a]);
        for (int b = 0; b < 3; ++b) {
            vd s = vd {};
            for (int i = 0; i < 4; ++i)
                s += (p[i].v[a] - xc) * g[i].v[b];
            F.m[a][b] = s;
        }
    }
    M3 R = G;
    if (corotated) {
        vm conv;
        warm_rotation(F, G, R, conv);
        for (int k = 0; k < count; ++k) {
            if (!conv[k]) {
                Mat3 Fk, Gk;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        Fk(a, b) = F.m[a][b][k];
                        Gk(a, b) = G.m[a][b][k];
                    }
                const Mat3 Rk = polar_rotation_warm(Fk, Gk);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        R.m[a][b][k] = Rk(a, b);
            }
            Mat3& out = *tets[k].rotation;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    out(a, b) = R.m[a][b][k];
        }
    }
    if (fint) {
        // H = R^T F - C0, sigma = lambda tr(H) I + mu (H + H^T), P = V R sigma, f_i = -P g_i.
        M3 H, sigma, P;
        mul_tn(R, F, H);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                H.m[a][b] -= C0.m[a][b];
        const vd ltr = lambda * (H.m[0][0] + H.m[1][1] + H.m[2][2]);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                sigma.m[a][b] = mu * (H.m[a][b] + H.m[b][a]) + (a == b ? ltr : vd {});
        mul(R, sigma, P);
        V3 f[4];
        for (int i = 0; i < 4; ++i)
            for (int a = 0; a < 3; ++a)
                f[i].v[a]
                    = V * (P.m[a][0] * g[i].v[0] + P.m[a][1] * g[i].v[1] + P.m[a][2] * g[i].v[2]);
        for (int k = 0; k < count; ++k)
            for (int i = 0; i < 4; ++i) {
                double* dst = fint + 3 * std::size_t(tets[k].nodes[i]);
                dst[0] -= f[i].v[0][k];
                dst[1] -= f[i].v[1][k];
                dst[2] -= f[i].v[2][k];
            }
    }
    if (!Kvals)
        return;
    V3 r[4];
    for (int i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a)
            r[i].v[a] = R.m[a][0] * g[i].v[0] + R.m[a][1] * g[i].v[1] + R.m[a][2] * g[i].v[2];
    const double scale = step ? step->scale : 1.0;
    const vd vl = V * (scale * lambda), vmu = V * (scale * mu);
    // Blocks (i, j), i <= j: B = vl r_i r_j^T + vmu r_j r_i^T + vmu (g_i . g_j) I; (j, i) = B^T.
    M3 B[10];
    int b = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j, ++b) {
            const vd gg
                = vmu * (g[i].v[0] * g[j].v[0] + g[i].v[1] * g[j].v[1] + g[i].v[2] * g[j].v[2]);
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c)
                    B[b].m[a][c] = vl * r[i].v[a] * r[j].v[c] + vmu * r[j].v[a] * r[i].v[c]
                        + (a == c ? gg : vd {});
        }
    if (step && step->kv) {
        // kv_i += sum_j B_ij v_j, with B_ji = B_ij^T
        V3 vel[4], y[4];
        for (int k = 0; k < W; ++k) {
            const P1TetView& t = tets[k < count ? k : 0];
            for (int i = 0; i < 4; ++i)
                for (int a = 0; a < 3; ++a)
                    vel[i].v[a][k] = step->v[3 * std::size_t(t.nodes[i]) + std::size_t(a)];
        }
        for (int i = 0; i < 4; ++i)
            for (int a = 0; a < 3; ++a)
                y[i].v[a] = vd {};
        b = 0;
        for (int i = 0; i < 4; ++i)
            for (int j = i; j < 4; ++j, ++b) {
                const M3& Bij = B[b];
                for (int a = 0; a < 3; ++a)
                    y[i].v[a] += Bij.m[a][0] * vel[j].v[0] + Bij.m[a][1] * vel[j].v[1]
                        + Bij.m[a][2] * vel[j].v[2];
                if (j == i)
                    continue;
                for (int a = 0; a < 3; ++a)
                    y[j].v[a] += Bij.m[0][a] * vel[i].v[0] + Bij.m[1][a] * vel[i].v[1]
                        + Bij.m[2][a] * vel[i].v[2];
            }
        for (int k = 0; k < count; ++k)
            for (int i = 0; i < 4; ++i) {
                double* dst = step->kv + 3 * std::size_t(tets[k].nodes[i]);
                dst[0] += y[i].v[0][k];
                dst[1] += y[i].v[1][k];
                dst[2] += y[i].v[2][k];
            }
    }
    for (int k = 0; k < count; ++k) {
        if (const int* blk = tets[k].block) {
            b = 0;
            for (int i = 0; i < 4; ++i)
                for (int j = i; j < 4; ++j, ++b) {
                    double* kij = Kvals + blk[4 * i + j];
                    const int lj = blk[16 + j];
#pragma GCC unroll 3
                    for (int c = 0; c < 3; ++c)
#pragma GCC unroll 3
                        for (int a = 0; a < 3; ++a)
                            kij[c * lj + a] += B[b].m[a][c][k];
                    if (j == i)
                        continue;
                    double* kji = Kvals + blk[4 * j + i];
                    const int li = blk[16 + i];
#pragma GCC unroll 3
                    for (int c = 0; c < 3; ++c)
#pragma GCC unroll 3
                        for (int a = 0; a < 3; ++a)
                            kji[c * li + a] += B[b].m[c][a][k];
                }
            continue;
        }
        const int* scatter = tets[k].scatter;
        b = 0;
        for (int i = 0; i < 4; ++i)
            for (int j = i; j < 4; ++j, ++b) {
                const int* sij = scatter + 3 * i * 12 + 3 * j;
                const int* sji = scatter + 3 * j * 12 + 3 * i;
                for (int a = 0; a < 3; ++a)
                    for (int c = 0; c < 3; ++c) {
                        const int s = sij[a * 12 + c];
                        if (s >= 0)
                            Kvals[s] += B[b].m[a][c][k];
                    }
                if (j == i)
                    continue;
                for (int a = 0; a < 3; ++a)
                    for (int c = 0; c < 3; ++c) {
                        const int s = sji[a * 12 + c];
                        if (s >= 0)
                            Kvals[s] += B[b].m[c][a][k];
                    }
            }
    }
}

} // namespace polycut::elasticity::detail
