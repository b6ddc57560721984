// Strips of sweep triangles coarsened to the blade resolution the scalpel path already uses.
#pragma once

#include "polycut/cut/cutter.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace polycut::cut::detail {

/// Sweep triangles after coarsening, with the input triangle each one starts at.
struct CoarseSweep {
    std::vector<Triangle> triangles;
    /// Per coarse triangle: the index of the first input triangle it stands for.
    std::vector<std::size_t> first;
    /// Per coarse triangle: whether a budget may stop a call after it; not between the two
    /// halves of a coarse quad (a call resumed at the quad's second half would re-sweep the
    /// input from there along other chords: cells cut twice by nearly coincident planes).
    std::vector<char> may_stop;
};

/// Runs of triangle pairs in the scalpel's order, (a0, b0, a1), (b0, b1, a1), (a1, b1, a2), ...
/// (docs/protocol.md `cut`; the corners shared bit for bit), are a blade moving through samples
/// (a_k, b_k). A sample is dropped, and its two quads merged with the next, while the blade has
/// moved less than `min_advance` [m] from the last kept sample, as the server holds `scalpel`
/// samples (Simulation::blade_min_advance), and only while every dropped sample's ends lie
/// within `tolerance` [m] of the coarse quad's edges (a turning stroke keeps its turns). Other
/// triangles pass unchanged. min_advance <= 0: a copy of the input.
CoarseSweep coarsen_strips(std::span<const Triangle> tris, double min_advance, double tolerance);

} // namespace polycut::cut::detail
