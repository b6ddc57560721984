// PNG input and output through libpng's simplified API, and tolerant image comparison.
#include "polycut/render/image.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <cstdlib>
#include <png.h>

namespace polycut::render {

namespace {

void check_buffer(const Image& image, const char* where) {
    if (image.width <= 0 || image.height <= 0)
        throw InputError(where, "image is empty");
    if (image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
        throw InputError(where, "rgba buffer size is not width * height * 4");
}

} // namespace

void write_png(const std::string& path, const Image& image) {
    check_buffer(image, "write_png");
    png_image png {};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGBA;
    if (!png_image_write_to_file(&png, path.c_str(), 0, image.rgba.data(), 0, nullptr)) {
        const std::string message = png.message;
        png_image_free(&png);
        throw FileError(path, 0, "cannot write PNG: " + message);
    }
}

Image read_png(const std::string& path) {
    png_image png {};
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str()))
        throw FileError(path, 0, std::string("cannot read PNG: ") + png.message);
    png.format = PNG_FORMAT_RGBA;
    Image image;
    image.width = static_cast<int>(png.width);
    image.height = static_cast<int>(png.height);
    image.rgba.resize(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
        const std::string message = png.message;
        png_image_free(&png);
        throw FileError(path, 0, "cannot decode PNG: " + message);
    }
    return image;
}

namespace {

int pixel_diff(const std::uint8_t* a, const std::uint8_t* b) {
    int diff = 0;
    for (int c = 0; c < 4; ++c)
        diff = std::max(diff, std::abs(int(a[c]) - int(b[c])));
    return diff;
}

void check_same_size(const Image& a, const Image& b) {
    check_buffer(a, "compare: first image");
    check_buffer(b, "compare: second image");
    if (a.width != b.width || a.height != b.height)
        throw InputError("compare",
            "image sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height)
                + " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

} // namespace

ImageDiff compare(const Image& a, const Image& b, int tolerance) {
    check_same_size(a, b);
    ImageDiff diff;
    const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
    for (std::size_t i = 0; i < pixels; ++i) {
        const int d = pixel_diff(&a.rgba[4 * i], &b.rgba[4 * i]);
        diff.max_channel_diff = std::max(diff.max_channel_diff, d);
        if (d > tolerance)
            ++diff.differing_pixels;
    }
    diff.differing_fraction = double(diff.differing_pixels) / double(pixels);
    return diff;
}

Image difference_image(const Image& a, const Image& b, int tolerance) {
    check_same_size(a, b);
    Image out = a;
    const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
    for (std::size_t i = 0; i < pixels; ++i) {
        std::uint8_t* p = &out.rgba[4 * i];
        if (pixel_diff(&a.rgba[4 * i], &b.rgba[4 * i]) > tolerance) {
            p[0] = 255, p[1] = 0, p[2] = 0;
        } else {
            for (int c = 0; c < 3; ++c)
                p[c] = static_cast<std::uint8_t>(p[c] / 3);
        }
        p[3] = 255;
    }
    return out;
}

} // namespace polycut::render
