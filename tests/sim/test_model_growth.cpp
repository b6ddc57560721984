// The step cost a cut may grow the model to (cutting.max_model_growth): element matrix entries,
// a cell other than a tet weighted 4 (setup.hpp element_cost).
#include "polycut/mesh/builders.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/simulation.hpp"
#include "setup.hpp"

#include <gtest/gtest.h>

namespace polycut::sim {
namespace {

TEST(ModelGrowth, ATetCountsItsEntriesAndAnyOtherCellFourTimesItsOwn) {
    mesh::BoxGrid g;
    g.cells = Eigen::Vector3i(2, 1, 1);
    // Kuhn: 12 tets of 4 nodes, (3 x 4)^2 = 144 entries each.
    EXPECT_DOUBLE_EQ(element_cost(mesh::tet_grid(g)), 12 * 144.0);
    // Hexahedra: (3 x 8)^2 = 576 entries each, weighted 4.
    EXPECT_DOUBLE_EQ(element_cost(mesh::hex_grid(g)), 2 * 4 * 576.0);
    // Two blocks merged into one 12-node box: (3 x 12)^2 = 1296, weighted 4.
    const mesh::Mesh merged = mesh::merged_hex_grid(g, 1.0, 1);
    ASSERT_EQ(merged.cells.size(), 1u);
    EXPECT_DOUBLE_EQ(element_cost(merged), 4 * 1296.0);
}

const char* kTetBlock = R"({"name": "growth_block",
  "geometry": {"type": "box", "origin": [-0.05, -0.05, 0], "size": [0.1, 0.1, 0.05], "cells": [4, 4, 2], "elements": "tet"},
  "method": "mvc", "cutting": {"method": "split"},
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.3, "density": 1000},
  "integrator": {"type": "implicit_euler", "dt": 0.01},
  "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-8},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
  "loads": {"gravity": [0, 0, -9.81]}})";

TEST(ModelGrowth, ASplitTetBlockGrowsByItsPolyhedraWeightedFour) {
    // The cut tets become polyhedra with more nodes, each now weighted 4: the growth the
    // stats report is that of the weighted sum, well above the plain entries' ratio. A model
    // this small (192 tets) is never refused, whatever the limit; the same cut through a block
    // above 10,400 tets' entries is.
    Simulation s(scene::parse_scene(kTetBlock));
    s.step();
    EXPECT_DOUBLE_EQ(s.mesh_stats().model_growth, 1.0);
    std::vector<std::array<Vec3, 3>> sweep {
        { Vec3(-0.06, 0.0101, 0.06), Vec3(0.06, 0.0101, 0.06), Vec3(-0.06, 0.0101, 0.02) },
        { Vec3(0.06, 0.0101, 0.06), Vec3(0.06, 0.0101, 0.02), Vec3(-0.06, 0.0101, 0.02) },
    };
    const CutSummary cut = s.cut(sweep);
    ASSERT_EQ(cut.status, CutSummary::Status::Applied) << cut.reason;
    const MeshStats st = s.mesh_stats();
    // Every tet the plane y = 10.1 mm crosses (the 4 x 1 column of blocks between y = 0 and
    // 25 mm, upper layer, cut above z = 20 mm: all 6 Kuhn tets of each crossed block that
    // reach the plane) gives two polyhedra of 4-6 nodes: (4 x 9 x 16 + ...) / 144 per tet at
    // least 2 x 4 = 8 times its tet's cost, far above the unweighted ratio of 2-4.
    EXPECT_GT(cut.cells_split, 0);
    const double uncut = 4 * 4 * 2 * 6 * 144.0;
    const double added_cells = double(cut.cells_after - cut.cells_before);
    EXPECT_GT(st.model_growth, 1.0 + 4 * 144.0 * added_cells / uncut);
    const auto with = [](std::string text, const std::string& cells, double limit) {
        const std::string from = R"("cells": [4, 4, 2])";
        text.replace(text.find(from), from.size(), R"("cells": )" + cells);
        const std::string split = R"("cutting": {"method": "split"})";
        text.replace(text.find(split), split.size(),
            R"("cutting": {"method": "split", "max_cells_per_tick": 0, "max_model_growth": )"
                + std::to_string(limit) + "}");
        return text;
    };
    Simulation small(scene::parse_scene(with(kTetBlock, "[4, 4, 2]", 1.0001)));
    small.step();
    EXPECT_EQ(small.cut(sweep).status, CutSummary::Status::Applied);
    // 16 x 16 x 8 blocks, 12,288 tets: 1,769,472 entries, above the floor; the same plane grows
    // it (4 times as many cells as the small block's, on 64 times the tets) by less.
    Simulation big(scene::parse_scene(with(kTetBlock, "[16, 16, 8]", 4)));
    big.step();
    ASSERT_EQ(big.cut(sweep).status, CutSummary::Status::Applied);
    const double growth = big.mesh_stats().model_growth;
    EXPECT_GT(growth, 1.0);
    EXPECT_LT(growth, st.model_growth);
    Simulation tight(scene::parse_scene(with(kTetBlock, "[16, 16, 8]", 0.99 * growth)));
    tight.step();
    const CutSummary refused = tight.cut(sweep);
    EXPECT_EQ(refused.status, CutSummary::Status::Failed);
    EXPECT_NE(refused.reason.find("max_model_growth"), std::string::npos) << refused.reason;
}

} // namespace
} // namespace polycut::sim
