// PNG-directory and mp4 frame sinks (see frame_sink.hpp).
#include "frame_sink.hpp"

#include "polycut/common/error.hpp"

#include <array>
#include <cstdio>
#include <filesystem>

namespace polycut::record {

std::string png_frame_name(long index) {
    std::array<char, 32> name {};
    std::snprintf(name.data(), name.size(), "frame_%06ld.png", index);
    return name.data();
}

namespace {

class PngSink final : public FrameSink {
public:
    explicit PngSink(std::string directory)
        : m_directory(std::move(directory)) {
        std::error_code error;
        std::filesystem::create_directories(m_directory, error);
        if (error || !std::filesystem::is_directory(m_directory)) {
            throw FileError(m_directory, 0, "cannot create the PNG directory: " + error.message());
        }
    }
    void write(long index, const render::Image& image) override {
        render::write_png(
            (std::filesystem::path(m_directory) / png_frame_name(index)).string(), image);
    }
    void finish() override { }
    std::string describe() const override { return m_directory + "/frame_*.png"; }

private:
    std::string m_directory;
};

class Mp4Sink final : public FrameSink {
public:
    explicit Mp4Sink(const Mp4Options& options)
        : m_pipe(options)
        , m_path(options.path) { }
    void write(long, const render::Image& image) override { m_pipe.write(image.rgba); }
    void finish() override { m_pipe.finish(); }
    std::string describe() const override { return m_path + " (" + m_pipe.codec() + ")"; }

private:
    FfmpegPipe m_pipe;
    std::string m_path;
};

} // namespace

std::unique_ptr<FrameSink> make_png_sink(const std::string& directory) {
    return std::make_unique<PngSink>(directory);
}

std::unique_ptr<FrameSink> make_mp4_sink(const Mp4Options& options) {
    return std::make_unique<Mp4Sink>(options);
}

} // namespace polycut::record
