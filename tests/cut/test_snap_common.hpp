// Shared helpers of the face-snapping tests: Kuhn tet blocks, sweeps, invariants for method `tet`.
#pragma once

#include "polycut/cut/invariants.hpp"
#include "polycut/cut/snap_cutter.hpp"
#include "polycut/mesh/builders.hpp"

#include <algorithm>
#include <gtest/gtest.h>
#include <random>
#include <vector>

namespace snaptest {

using namespace polycut;

/// A cube [0, size]^3 of n^3 Kuhn blocks (6 n^3 tets).
inline mesh::Mesh tet_block(int n, double size = 0.1) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(size);
    g.cells = Eigen::Vector3i(n, n, n);
    return mesh::tet_grid(g, mesh::TetSplit::Kuhn6);
}

/// n random triangles: centres uniform in [lo, hi]^3, corners within `half` of them per axis.
inline std::vector<cut::Triangle> random_soup(
    unsigned seed, int n, double lo, double hi, double half) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> in(lo, hi), off(-half, half);
    std::vector<cut::Triangle> soup;
    for (int k = 0; k < n; ++k) {
        const Vec3 c(in(rng), in(rng), in(rng));
        soup.push_back({ c + Vec3(off(rng), off(rng), off(rng)),
            c + Vec3(off(rng), off(rng), off(rng)), c + Vec3(off(rng), off(rng), off(rng)) });
    }
    return soup;
}

/// Two triangles covering the square through `o` spanned by unit u, v (half-size r).
inline std::vector<cut::Triangle> square(const Vec3& o, const Vec3& u, const Vec3& v, double r) {
    const Vec3 a = o - r * u - r * v, b = o + r * u - r * v, c = o + r * u + r * v,
               d = o - r * u + r * v;
    return { { a, b, c }, { a, c, d } };
}

/// Issue 5 item 6 for face snapping: positive tets, closed oriented boundary, finite, consistent
/// face table, rest volume within 1e-3 of v0.
inline cut::CutInvariants expect_ok(const mesh::Mesh& m, double v0, double vtol = 1e-3) {
    cut::InvariantOptions io;
    io.volume_tol = vtol;
    io.require_convex = false;
    io.planarity_tol = 1e-9;
    const auto inv = cut::check_cut_invariants(m, v0, io);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
    for (const auto& cell : m.cells)
        EXPECT_EQ(cell.shape, mesh::CellShape::Tet);
    return inv;
}

/// Weights of new nodes refer to pre-call nodes and sum to one; ids are in range.
inline void expect_report_consistent(const mesh::Mesh& m, const cut::CutReport& r) {
    EXPECT_EQ(r.nodes_after, m.num_nodes());
    EXPECT_EQ(r.cells_after, m.num_cells());
    for (const auto& o : r.new_nodes) {
        double sum = 0;
        for (const auto& [n, w] : o.weights) {
            EXPECT_GE(n, 0);
            EXPECT_LT(n, r.nodes_before);
            sum += w;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);
        EXPECT_GE(o.node, 0);
        EXPECT_LT(o.node, m.num_nodes());
    }
    for (const auto& [n, X0] : r.moved_nodes) {
        EXPECT_GE(n, 0);
        EXPECT_LT(n, m.num_nodes());
        EXPECT_TRUE(X0.allFinite());
    }
    if (!r.node_map.empty()) {
        EXPECT_EQ(Index(r.node_map.size()), r.nodes_before);
    }
    if (!r.cell_map.empty()) {
        EXPECT_EQ(Index(r.cell_map.size()), r.cells_before);
    }
}

/// Smallest aspect ratio and largest dihedral angle [rad] over the tets of m, and the number of
/// tets degenerate by the options' thresholds (002 sec. 3.2.3: aspect < 0.01 or an angle
/// > 0.99 pi by default).
struct Quality {
    double min_aspect = 1, max_dihedral = 0;
    Index degenerate = 0;
};
inline Quality quality(const mesh::Mesh& m, const cut::SnapOptions& o) {
    Quality q;
    for (const auto& cell : m.cells) {
        const auto X = [&](std::size_t i) { return m.rest[std::size_t(cell.nodes[i])]; };
        const double a = cut::tet_aspect_ratio(X(0), X(1), X(2), X(3));
        double d = 0;
        for (double t : cut::tet_dihedral_angles(X(0), X(1), X(2), X(3)))
            d = std::max(d, t);
        q.min_aspect = std::min(q.min_aspect, a);
        q.max_dihedral = std::max(q.max_dihedral, d);
        q.degenerate += a < o.degenerate_aspect || d > o.large_dihedral ? 1 : 0;
    }
    return q;
}

/// A [0, 0.1]^3 block of n^3 grid cells split into tets, with interior nodes moved by up to
/// `jitter` times the spacing h = 0.1 / n in each coordinate [m].
inline mesh::Mesh jittered_block(int n, mesh::TetSplit split, double jitter, std::mt19937& rng) {
    mesh::BoxGrid g;
    g.hi = Vec3::Constant(0.1);
    g.cells = Eigen::Vector3i(n, n, n);
    auto m = mesh::tet_grid(g, split);
    std::uniform_real_distribution<double> J(-jitter * 0.1 / n, jitter * 0.1 / n);
    for (auto& X : m.rest)
        if ((X.array() > 1e-9).all() && (X.array() < 0.1 - 1e-9).all())
            X += Vec3(J(rng), J(rng), J(rng));
    return m;
}

inline std::size_t hash_mesh(const mesh::Mesh& m) {
    std::size_t h = m.rest.size() * 1000003u + m.faces.size() * 7919u + m.cells.size();
    for (const Vec3& x : m.rest)
        h = h * 31 + std::hash<double>()(x.x() + 2 * x.y() + 3 * x.z());
    for (const auto& f : m.faces) {
        for (Index n : f.nodes)
            h = h * 131 + std::size_t(n);
        h = h * 7 + std::size_t(f.tag);
    }
    return h;
}

/// Sweep of a straight blade from `b0`-`b1` translated by `step` per sample (`samples` samples,
/// two triangles per move).
inline std::vector<cut::Triangle> blade_sweep(
    const Vec3& b0, const Vec3& b1, const Vec3& step, int samples) {
    std::vector<cut::Triangle> out;
    for (int i = 0; i + 1 < samples; ++i) {
        const Vec3 p = b0 + double(i) * step, q = b1 + double(i) * step;
        out.push_back({ p, q, Vec3(q + step) });
        out.push_back({ p, Vec3(q + step), Vec3(p + step) });
    }
    return out;
}

} // namespace snaptest
