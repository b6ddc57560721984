// Procedural test scenes for the renderer: a block, the block with a V-shaped notch whose faces
// are tagged cut, and the notch opened by displacing one lip. Plain arrays, as the sim hands out.
#pragma once

#include "polycut/render/renderer.hpp"

#include <cstdint>
#include <vector>

namespace polycut::render::test {

/// An owning triangle surface.
struct TestSurface {
    std::vector<float> positions; ///< (#V x 3) [m]
    std::vector<std::uint32_t> triangles; ///< (#T x 3)
    std::vector<std::uint8_t> tags; ///< (#T)

    SurfaceArrays arrays() const { return { positions, triangles, tags }; }
    DrawList draw_list() const { return { arrays(), {}, {}, {}, {} }; }
};

/// Block dimensions [m] and notch geometry.
struct BlockSpec {
    double length = 0.100; ///< x [m]
    double width = 0.060; ///< y [m]
    double height = 0.040; ///< z [m]
    double notch_x = 0.048; ///< x of the notch root [m]
    double notch_half_width = 0.012; ///< half opening of the notch at the top [m]
    double notch_depth = 0.0; ///< 0 = uncut block [m]
    double opening = 0.0; ///< x displacement of the right lip's top [m] (retraction)
};

/// A box surface on a 4 mm grid (duplicate vertices along box edges); the top face has a V notch
/// of the given depth along y, its faces tagged cut; points right of the notch root move by
/// opening * (z / height)^2 * (1 - (x - notch_x) / (length - notch_x)) in x, so the lip opens
/// and the far end stays put.
TestSurface make_block(const BlockSpec& spec = {});

/// A bumpy sphere ("blob") of radius ~`radius` [m] with `slices` x `stacks` quads
/// (2 slices (stacks - 1) triangles); a band around the equator is tagged cut.
TestSurface make_blob(int slices, int stacks, double radius = 0.05);

/// The camera used by the golden tests: frame() of the uncut block, for width / height.
Camera block_camera(int width, int height);

/// Pixels of `image` that look like fresh cut tissue: red clearly dominating green and blue.
long count_cut_coloured(const Image& image);

} // namespace polycut::render::test
