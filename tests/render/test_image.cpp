// PNG round trip and image comparison.
#include "polycut/common/error.hpp"
#include "polycut/render/image.hpp"

#include <filesystem>
#include <gtest/gtest.h>

namespace polycut::render::test {
namespace {

Image gradient(int width, int height) {
    Image image { width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 4) };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = &image.rgba[(std::size_t(y) * width + x) * 4];
            p[0] = std::uint8_t(x), p[1] = std::uint8_t(y), p[2] = std::uint8_t(x ^ y), p[3] = 255;
        }
    return image;
}

TEST(Image, PngRoundTripIsExact) {
    const Image image = gradient(37, 23);
    const auto path = std::filesystem::temp_directory_path() / "polycut_test_image.png";
    write_png(path.string(), image);
    const Image back = read_png(path.string());
    std::filesystem::remove(path);
    EXPECT_EQ(back.width, 37);
    EXPECT_EQ(back.height, 23);
    EXPECT_EQ(back.rgba, image.rgba);
}

TEST(Image, CompareCountsPixelsBeyondTolerance) {
    const Image a = gradient(10, 10);
    Image b = a;
    b.rgba[0] += 5; // within tolerance 8
    b.rgba[4 * 7 + 2] ^= 64; // pixel 7 differs by 64
    b.rgba[4 * 9 + 1] += 9; // pixel 9 differs by 9
    const ImageDiff diff = compare(a, b, 8);
    EXPECT_EQ(diff.differing_pixels, 2);
    EXPECT_EQ(diff.max_channel_diff, 64);
    EXPECT_DOUBLE_EQ(diff.differing_fraction, 0.02);
    const Image marked = difference_image(a, b, 8);
    EXPECT_EQ(marked.rgba[4 * 7], 255);
    EXPECT_EQ(marked.rgba[4 * 7 + 1], 0);
}

TEST(Image, ErrorsAreTyped) {
    EXPECT_THROW(read_png("/nonexistent/polycut.png"), FileError);
    EXPECT_THROW(write_png("/nonexistent/dir/out.png", gradient(2, 2)), FileError);
    EXPECT_THROW(write_png("/tmp/empty.png", Image {}), InputError);
    EXPECT_THROW(compare(gradient(2, 2), gradient(3, 2), 0), InputError);
}

} // namespace
} // namespace polycut::render::test
