// libFuzzer target: geometric fuzz of the cutters (issue 14 item 6). The input is read as up to
// 8 sweep triangles (9 floats each, mapped into a box 1.5x the tissue's), cut into a small tet
// grid with either cutter, then stepped: cut() must not throw, and no position may become
// non-finite.
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace {
std::unique_ptr<polycut::sim::Simulation> make(bool snap) {
    const std::string text = std::string(R"({"name": "fuzz",
      "geometry": {"type": "box", "origin": [0, 0, 0], "size": [0.03, 0.03, 0.02],
                   "cells": [3, 3, 2], "elements": "tet"},
      "method": ")")
        + (snap ? "tet" : "mvc") + R"(",
      "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000,
                   "rayleigh_stiffness": 0.02},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667},
      "solver": {"type": "pcg", "preconditioner": "jacobi", "tolerance": 1e-8},
      "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
      "cutting": {"method": ")"
        + (snap ? "snap" : "split") + R"("}})";
    return std::make_unique<polycut::sim::Simulation>(polycut::scene::parse_scene(text));
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using polycut::Vec3;
    if (size < 1 + 36) {
        return 0;
    }
    const bool snap = data[0] % 2 == 0;
    std::vector<std::array<Vec3, 3>> tris;
    for (std::size_t off = 1; off + 36 <= size && tris.size() < 8; off += 36) {
        std::array<Vec3, 3> t;
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < 3; ++k) {
                std::uint32_t bits = 0;
                std::memcpy(&bits, data + off + 12 * c + 4 * k, 4);
                // [0, 1) -> [-0.25, 1.25] of the tissue's extent along k
                const double u = double(bits) / 4294967296.0;
                const double extent = k == 2 ? 0.02 : 0.03;
                t[std::size_t(c)][k] = (-0.25 + 1.5 * u) * extent;
            }
        }
        tris.push_back(t);
    }
    static std::unique_ptr<polycut::sim::Simulation> sims[2];
    auto& sim = sims[snap ? 0 : 1];
    if (!sim) {
        sim = make(snap);
    }
    sim->reset();
    try {
        (void)sim->cut(tris);
    } catch (...) {
        std::abort(); // cut() never throws
    }
    for (int k = 0; k < 2; ++k) {
        (void)sim->step();
    }
    for (const Vec3& p : sim->positions()) {
        if (!p.allFinite()) {
            std::abort();
        }
    }
    return 0;
}
