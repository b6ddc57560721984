// RGBA8 images, PNG files and tolerant image comparison (for golden tests and recorders).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace polycut::render {

/// An 8-bit RGBA image, rows top to bottom, pixels left to right: rgba (height x width x 4).
struct Image {
    int width = 0; ///< [px]
    int height = 0; ///< [px]
    std::vector<std::uint8_t> rgba; ///< (height x width x 4), row 0 is the top row

    /// Pointer to the 4 bytes of pixel (x, y), y = 0 at the top. No bounds check.
    const std::uint8_t* pixel(int x, int y) const {
        return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4;
    }
};

/// Writes `image` as an 8-bit RGBA PNG. Throws FileError if the file cannot be written and
/// InputError if the image is empty or its buffer size is not width * height * 4.
void write_png(const std::string& path, const Image& image);

/// Reads a PNG (any bit depth or colour type) as RGBA8. Throws FileError if it cannot.
Image read_png(const std::string& path);

/// Per-pixel difference of two images of the same size.
struct ImageDiff {
    int max_channel_diff = 0; ///< largest |a - b| over all pixels and channels [0, 255]
    long differing_pixels = 0; ///< pixels whose largest channel difference > tolerance
    double differing_fraction = 0; ///< differing_pixels / (width * height)
};

/// Compares two images channel by channel; a pixel differs if any channel differs by more than
/// `tolerance` [0, 255]. Throws InputError if the sizes differ.
ImageDiff compare(const Image& a, const Image& b, int tolerance);

/// An image showing where a and b differ: differing pixels red, others a dimmed copy of a.
Image difference_image(const Image& a, const Image& b, int tolerance);

} // namespace polycut::render
