// sim::estimate (issue 14 item 3): the memory a scene is estimated to need, before anything is
// built, against the heap the built simulation really holds after a step (glibc mallinfo2).
#include "polycut/sim/estimate.hpp"
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>
#include <malloc.h>

using namespace polycut;

namespace {
std::string box(int n, const char* elements, const char* method) {
    return std::string(R"({"name": "b", "geometry": {"type": "box", "size": [0.1, 0.1, 0.05],
      "cells": [)")
        + std::to_string(n) + ", " + std::to_string(n) + ", " + std::to_string(n / 2)
        + R"(], "elements": ")" + elements + R"("}, "method": ")" + method + R"(",
      "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-3},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
      "loads": {"gravity": [0, 0, -9.81]}})";
}

double heap_bytes() {
    return double(mallinfo2().uordblks);
}
} // namespace

TEST(SceneEstimate, BoundsTheHeapOfTheBuiltSceneWithinAFactorOfThree) {
    for (const auto& [elements, method] : { std::pair { "tet", "tet" }, { "hex", "hex" } }) {
        for (const int n : { 8, 16 }) {
            const scene::Scene scene = scene::parse_scene(box(n, elements, method));
            const sim::SceneEstimate e = sim::estimate(scene);
            const double before = heap_bytes();
            double used = 0;
            {
                sim::Simulation s(scene);
                s.step();
                used = heap_bytes() - before;
                EXPECT_NEAR(e.cells, double(s.cell_count()), 1e-9) << elements << " " << n;
            }
            EXPECT_TRUE(e.known);
            EXPECT_GE(e.bytes, used) << elements << " " << n;
            EXPECT_LE(e.bytes, 3.0 * used) << elements << " " << n;
            std::printf("%s %d^2x%d: estimate %.1f MB, heap %.1f MB (x%.2f)\n", elements, n, n / 2,
                e.bytes / 1e6, used / 1e6, e.bytes / used);
        }
    }
}

TEST(SceneEstimate, TheIssuesOversizeBoxIsFarAboveAnyMachine) {
    // 200 x 200 x 100 blocks of 6 tets (issue 14: 16 s of stall, then std::bad_alloc at 4 GB).
    scene::Scene scene = scene::parse_scene(box(8, "tet", "tet"));
    scene.geometry.cells = Eigen::Vector3i(200, 200, 100);
    const sim::SceneEstimate e = sim::estimate(scene);
    EXPECT_EQ(e.cells, 24e6);
    EXPECT_GT(e.bytes, 50e9);
}
