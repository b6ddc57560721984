// Where rendered frames go: numbered PNG files in a directory, or an mp4 through ffmpeg.
#pragma once

#include "ffmpeg_pipe.hpp"
#include "polycut/render/image.hpp"

#include <memory>
#include <string>

namespace polycut::record {

/// Receives rendered frames in order.
class FrameSink {
public:
    virtual ~FrameSink() = default;
    FrameSink() = default;
    FrameSink(const FrameSink&) = delete;
    FrameSink& operator=(const FrameSink&) = delete;

    /// Stores frame number `index` (0, 1, 2, ...). Throws polycut::Error on I/O failure.
    virtual void write(long index, const render::Image& image) = 0;
    /// Flushes and closes; throws polycut::Error if the output is not complete. Idempotent.
    virtual void finish() = 0;
    /// Human-readable description of the output, e.g. "out/demo.mp4 (libx264)".
    virtual std::string describe() const = 0;
};

/// File name of frame `index` in a PNG directory: "frame_000123.png".
std::string png_frame_name(long index);

/// Writes DIR/frame_%06d.png; creates DIR (and parents) if missing.
std::unique_ptr<FrameSink> make_png_sink(const std::string& directory);

/// Encodes an mp4 (ffmpeg_pipe.hpp); frames must be options.width x options.height.
std::unique_ptr<FrameSink> make_mp4_sink(const Mp4Options& options);

} // namespace polycut::record
