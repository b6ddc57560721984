// A 5 x 7 pixel bitmap font (digits, upper-case letters, a little punctuation) for labelling
// plots drawn straight into an RGBA image, so the benchmark needs no Python or font library.
#pragma once

#include "polycut/render/image.hpp"

#include <array>
#include <cstdint>
#include <string_view>

namespace polycut::bench {

/// An RGB colour, 0..255 per channel.
using Colour = std::array<std::uint8_t, 3>;

/// Glyph cell size: 5 x 7 pixels plus one column of spacing, at scale 1 [px].
inline constexpr int kGlyphWidth = 6;
inline constexpr int kGlyphHeight = 7;

/// Sets pixel (x, y) (y down from the top) if it is inside the image.
void put_pixel(render::Image& image, int x, int y, const Colour& colour);
/// Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
void fill_rect(render::Image& image, int x0, int y0, int x1, int y1, const Colour& colour);

/// Draws `text` with its top-left corner at (x, y), each font pixel a scale x scale block.
/// Lower-case letters are drawn as upper case; characters without a glyph as a blank.
/// Returns the x just after the last character [px].
int draw_text(
    render::Image& image, int x, int y, std::string_view text, const Colour& colour, int scale = 1);

/// Width of `text` at `scale` [px].
int text_width(std::string_view text, int scale = 1);

} // namespace polycut::bench
