// Shared helpers of the cut::CutPipeline tests (test_pipeline.cpp, test_recut.cpp): unit blocks
// for either cutter, the pipeline's options, and the invariants every cut must keep.
#pragma once

#include "polycut/cut/invariants.hpp"
#include "polycut/cut/pipeline.hpp"
#include "polycut/mesh/builders.hpp"

#include <gtest/gtest.h>

namespace polycut::cut::pipelinetest {

/// The unit cube in n^3 grid cells: Kuhn tets for face snapping, hexes for cell splitting.
inline mesh::Mesh block(bool tets, int n = 6) {
    mesh::BoxGrid g;
    g.hi = Vec3(1, 1, 1);
    g.cells = Eigen::Vector3i(n, n, n);
    return tets ? mesh::tet_grid(g) : mesh::hex_grid(g);
}

inline PipelineOptions options(bool snap) {
    PipelineOptions o;
    o.method = snap ? CutMethod::Snap : CutMethod::Split;
    return o;
}

/// The cut invariants of DESIGN.md sec. 3 with the rest volume kept to 1e-9 (cell splitting)
/// or to face snapping's volume budget, 1e-3 (it moves skin nodes onto the blade).
inline void expect_cut_invariants(const mesh::Mesh& m, const mesh::Mesh& uncut, bool snap) {
    InvariantOptions io;
    io.volume_tol = snap ? 1e-3 : 1e-9;
    const CutInvariants inv = check_cut_invariants(m, uncut.rest_volume(), io);
    EXPECT_TRUE(inv.ok()) << inv.first_problem;
}

} // namespace polycut::cut::pipelinetest
