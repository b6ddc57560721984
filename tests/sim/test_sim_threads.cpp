// Threads through the facade (issue 18): a CGAL-meshed organ stepped with two threads gives the
// same state hash run after run, and stays within round-off of the serial run.
#include "polycut/sim/simulation.hpp"

#include <gtest/gtest.h>
#include <memory>

using namespace polycut;

namespace {
std::string organ(int threads, const std::string& solver) {
    return R"({"name": "organ_threads",
      "geometry": {"type": "implicit", "shape": "blob", "cell_size": 0.008, "seed": 0},
      "method": "tet",
      "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.45, "density": 1000, "rayleigh_stiffness": 0.01},
      "integrator": {"type": "implicit_euler", "dt": 0.0166667, "threads": )"
        + std::to_string(threads) + R"(},
      "solver": )"
        + solver + R"(,
      "fixed": [{"box": {"min": [-0.06, -0.05, -0.03], "max": [0.06, 0.04, -0.012]}}],
      "loads": {"gravity": [0, 0, -9.81]}})";
}

const std::string kAmg = R"({"type": "pcg", "preconditioner": "amg", "tolerance": 1e-1,
    "warm_start": "extrapolated", "refactor_iterations": 10})";
const std::string kTight = R"({"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-12,
    "max_iterations": 20000})";

std::unique_ptr<sim::Simulation> run(int threads, const std::string& solver, int steps) {
    auto s = std::make_unique<sim::Simulation>(scene::parse_scene(organ(threads, solver)));
    for (int k = 0; k < steps; ++k) {
        const sim::StepReport r = s->step();
        EXPECT_FALSE(r.rolled_back);
    }
    return s;
}
} // namespace

TEST(SimThreads, TwoThreadsRepeatBitForBit) {
    const auto a = run(2, kAmg, 15);
    const auto b = run(2, kAmg, 15);
    EXPECT_EQ(a->state_hash(), b->state_hash());
    EXPECT_GT(a->positions().size(), 300u);
}

TEST(SimThreads, OneAndTwoThreadsAgreeToRoundOff) {
    // Solved to 1e-12, the runs differ by the order of the assembly's sums only: displacements
    // agree to 1e-8 of the largest one.
    const auto a = run(1, kTight, 10);
    const auto b = run(2, kTight, 10);
    ASSERT_EQ(a->positions().size(), b->positions().size());
    double worst = 0, largest = 0;
    const std::vector<Vec3> rest
        = sim::Simulation(scene::parse_scene(organ(1, kTight))).positions();
    for (std::size_t i = 0; i < rest.size(); ++i) {
        worst = std::max(worst, (a->positions()[i] - b->positions()[i]).norm());
        largest = std::max(largest, (a->positions()[i] - rest[i]).norm());
    }
    EXPECT_GT(largest, 1e-4); // it sagged [m]
    EXPECT_LE(worst, 1e-8 * largest);
}
