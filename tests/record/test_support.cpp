// Recorder test helpers (see test_support.hpp).
#include "test_support.hpp"

#include "ffmpeg_pipe.hpp"
#include "subprocess.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace polycut::record::test {

BoxSurface make_box(double sx, double sy, double sz, std::uint8_t top_tag) {
    BoxSurface b;
    for (int k = 0; k < 8; ++k) {
        b.positions.push_back(static_cast<float>((k & 1) ? sx : 0.0));
        b.positions.push_back(static_cast<float>((k & 2) ? sy : 0.0));
        b.positions.push_back(static_cast<float>((k & 4) ? sz : 0.0));
    }
    // Quads as (a, b, c, d), counter-clockwise seen from outside; the +z top first.
    const std::uint32_t quads[6][4] = { { 4, 5, 7, 6 }, { 0, 2, 3, 1 }, { 0, 1, 5, 4 },
        { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
    for (int f = 0; f < 6; ++f) {
        const auto* q = quads[f];
        b.triangles.insert(b.triangles.end(), { q[0], q[1], q[2], q[0], q[2], q[3] });
        b.tags.insert(b.tags.end(), 2, f == 0 ? top_tag : std::uint8_t(1));
    }
    return b;
}

std::string scratch_dir(const std::string& name) {
    const std::filesystem::path dir
        = std::filesystem::path(POLYCUT_BINARY_DIR) / "Testing" / "record" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

std::map<std::string, std::string> probe_video(const std::string& path) {
    const std::string ffprobe = find_executable("ffprobe");
    if (ffprobe.empty()) {
        return {};
    }
    const auto [code, out] = run_command({ ffprobe, "-v", "error", "-count_frames",
        "-select_streams", "v:0", "-show_entries", "stream=width,height,nb_read_frames,codec_name",
        "-of", "default=noprint_wrappers=1", path });
    std::map<std::string, std::string> fields;
    if (code != 0) {
        return fields;
    }
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        if (const auto eq = line.find('='); eq != std::string::npos) {
            fields[line.substr(0, eq)] = line.substr(eq + 1);
        }
    }
    return fields;
}

long count_cut_pixels(const render::Image& image) {
    long count = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            const int r = p[0], g = p[1], b = p[2];
            if (r >= 40 && g * 10 < r * 4 && b * 10 < r * 4) {
                ++count;
            }
        }
    }
    return count;
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

} // namespace polycut::record::test
