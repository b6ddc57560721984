// An ffmpeg child process fed raw RGBA frames through a pipe, encoding an mp4 (libx264 when this
// ffmpeg has it, else MPEG-4 part 2). SIGPIPE is ignored process-wide so a dying ffmpeg turns into
// a write error (EPIPE) reported with the tail of ffmpeg's own stderr, never a silent kill.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <sys/types.h>

namespace polycut::record {

/// Settings of an mp4 encode.
struct Mp4Options {
    std::string path; ///< output file (overwritten)
    int width = 640; ///< [px], even
    int height = 480; ///< [px], even
    double fps = 60; ///< frames per second of the video [1/s], > 0
    int crf = 20; ///< libx264 quality (lower = better, 0..51); mpeg4 uses -q:v 3 instead
    /// ffmpeg executable: a name looked up on PATH, or a path. Empty: $POLYCUT_FFMPEG, else
    /// "ffmpeg".
    std::string ffmpeg;
};

/// The ffmpeg executable `name` resolves to (a path with '/' is taken as is if executable; else
/// the first executable match on PATH), or "" if there is none.
std::string find_executable(const std::string& name);

/// True if `ffmpeg -encoders` lists libx264.
bool ffmpeg_has_libx264(const std::string& ffmpeg_path);

/// A running ffmpeg encode. Not copyable; the destructor kills an unfinished encode.
class FfmpegPipe {
public:
    /// Starts ffmpeg. Throws polycut::Error with a clear message if ffmpeg is missing (naming the
    /// package to install), if the size is odd or the fps is not positive, or if it cannot start.
    explicit FfmpegPipe(const Mp4Options& options);
    ~FfmpegPipe();
    FfmpegPipe(const FfmpegPipe&) = delete;
    FfmpegPipe& operator=(const FfmpegPipe&) = delete;

    /// Writes one frame: rgba (height x width x 4), top row first. Throws polycut::Error if
    /// ffmpeg has exited (with its exit status and last stderr lines) or the size is wrong.
    void write(std::span<const std::uint8_t> rgba);
    /// Closes the pipe and waits for ffmpeg; throws polycut::Error if it failed. Idempotent.
    void finish();

    /// The codec in use: "libx264" or "mpeg4".
    const std::string& codec() const { return m_codec; }
    /// Frames written so far.
    long frames() const { return m_frames; }

private:
    std::string failure(const std::string& what);

    Mp4Options m_options;
    std::string m_codec;
    std::string m_log_path; ///< ffmpeg's stderr goes here
    pid_t m_pid = -1;
    int m_fd = -1; ///< write end of ffmpeg's stdin
    long m_frames = 0;
};

} // namespace polycut::record
