// Fuzz-style robustness: many random sweep triangles on small meshes with every invariant checked
// after each cut (issue 5 item 8), fixed seeds.
#include "polycut/common/error.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/cut/invariants.hpp"
#include "polycut/mesh/builders.hpp"

#include <cstdlib>
#include <gtest/gtest.h>
#include <iostream>
#include <map>
#include <random>

using namespace polycut;

namespace {
mesh::Mesh small_block(bool tets) {
    mesh::BoxGrid g;
    g.lo = Vec3::Zero();
    g.hi = Vec3::Constant(0.02);
    g.cells = Eigen::Vector3i(2, 2, 2);
    return tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
}

struct FuzzStats {
    double max_volume_error = 0, min_volume_ratio = 1, max_convexity = 0;
    Index cells = 0, nodes = 0;
    double cut_ms = 0;
};

FuzzStats fuzz(mesh::Mesh m, unsigned seed, int sweeps, double snap = cut::CutOptions {}.snap) {
    FuzzStats st;
    cut::CutOptions opt;
    opt.snap = snap;
    cut::InvariantOptions io;
    io.volume_tol = 1e-6;
    const double v0 = m.rest_volume();
    cut::Cutter cutter(m, opt);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.005, 0.025);
    std::uniform_real_distribution<double> s(0.0005, 0.004);
    std::normal_distribution<double> g(0, 1);
    for (int k = 0; k < sweeps; ++k) {
        const Vec3 c(u(rng), u(rng), u(rng));
        const double r = s(rng);
        cut::Triangle t;
        for (auto& p : t)
            p = c + r * Vec3(g(rng), g(rng), g(rng));
        // Sometimes snap a corner to a grid node or align with a grid plane: degenerate cases.
        if (k % 7 == 0)
            t[0] = Vec3(0.01, 0.01, 0.01);
        if (k % 11 == 0)
            for (auto& p : t)
                p.x() = 0.01;
        try {
            st.cut_ms += cutter.cut(std::span<const cut::Triangle>(&t, 1)).elapsed_ms;
        } catch (const InputError&) {
            continue;
        }
        const auto inv = cut::check_cut_invariants(m, v0, io);
        st.max_volume_error = std::max(st.max_volume_error, inv.volume_error);
        st.min_volume_ratio = std::min(st.min_volume_ratio, inv.min_volume_ratio);
        st.max_convexity = std::max(st.max_convexity, inv.max_convexity_violation);
        if (!inv.ok() && std::getenv("CUT_DEBUG")) {
            std::map<std::pair<Index, Index>, std::vector<Index>> edges;
            for (Index f : m.boundary_faces()) {
                const auto& l = m.faces[std::size_t(f)].nodes;
                for (std::size_t i = 0; i < l.size(); ++i)
                    edges[{ std::min(l[i], l[(i + 1) % l.size()]),
                              std::max(l[i], l[(i + 1) % l.size()]) }]
                        .push_back(f);
            }
            for (const auto& [e, fs] : edges)
                if (fs.size() != 2) {
                    std::cerr << "edge " << e.first << "-" << e.second << " faces";
                    for (Index f : fs) {
                        const auto& F = m.faces[std::size_t(f)];
                        std::cerr << "\n  f" << f << " tag " << int(F.tag) << " owner " << F.owner
                                  << " parent " << F.parent << " nodes";
                        for (Index n : F.nodes)
                            std::cerr << " " << n;
                    }
                    std::cerr << "\n";
                }
            std::cerr << "triangle " << t[0].transpose() << " | " << t[1].transpose() << " | "
                      << t[2].transpose() << "\n";
        }
        EXPECT_TRUE(inv.ok()) << "sweep " << k << ": " << inv.first_problem;
        if (!inv.ok())
            break;
    }
    st.cells = m.num_cells();
    st.nodes = m.num_nodes();
    return st;
}
} // namespace

void print(const char* what, const FuzzStats& s) {
    std::cout << what << ": max volume error " << s.max_volume_error << ", min cell volume ratio "
              << s.min_volume_ratio << ", max convexity violation " << s.max_convexity << ", "
              << s.cells << " cells, " << s.nodes << " nodes, cut time " << s.cut_ms << " ms\n";
}

// 1,000 random sweeps in 10 episodes of 100 on a fresh 2x2x2 block each (hexes and Kuhn tets
// alternating), every invariant after each sweep; volume within 1e-6 (snapped nodes leave cut
// faces off-plane by up to snap * h, and later splits of one side re-triangulate them).
TEST(CutFuzz, ThousandRandomSweeps) {
    for (unsigned episode = 0; episode < 10; ++episode) {
        const auto st = fuzz(small_block(episode % 2 == 1), 100 + episode, 100);
        print(episode % 2 ? "tet episode" : "hex episode", st);
        EXPECT_LT(st.max_volume_error, 1e-6);
        EXPECT_LT(st.max_convexity, 2e-2);
    }
}
