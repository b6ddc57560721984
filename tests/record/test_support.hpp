// Shared helpers of the recorder tests: a small procedural surface, a scratch directory, ffprobe,
// and counting "cut-coloured" pixels.
#pragma once

#include "polycut/render/image.hpp"
#include "polycut/render/shaded_mesh.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace polycut::record::test {

/// An axis-aligned box surface (12 triangles); face 0 (the +z top) tagged `top_tag`.
struct BoxSurface {
    std::vector<float> positions;
    std::vector<std::uint32_t> triangles;
    std::vector<std::uint8_t> tags;
    render::SurfaceArrays arrays() const { return { positions, triangles, tags }; }
};
BoxSurface make_box(double sx, double sy, double sz, std::uint8_t top_tag = 1);

/// A fresh empty directory under the build tree's Testing/record/<name>.
std::string scratch_dir(const std::string& name);

/// `ffprobe -count_frames` of the first video stream: keys width, height, nb_read_frames,
/// codec_name. Empty when ffprobe is missing or fails.
std::map<std::string, std::string> probe_video(const std::string& path);

/// Pixels whose colour is the cut colour's hue (deep red: r well above g and b); skin (pink,
/// g/r ~ 0.75) and the grey-blue background never count.
long count_cut_pixels(const render::Image& image);

/// The bytes of a file ("" if unreadable).
std::string read_bytes(const std::string& path);

} // namespace polycut::record::test
