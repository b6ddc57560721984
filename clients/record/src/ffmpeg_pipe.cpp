// ffmpeg child process behind a pipe (see ffmpeg_pipe.hpp).
#include "ffmpeg_pipe.hpp"

#include "polycut/common/error.hpp"

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace polycut::record {

namespace {

bool is_executable(const std::string& path) {
    struct stat st { };
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)
        && ::access(path.c_str(), X_OK) == 0;
}

std::string format_fps(double fps) {
    std::array<char, 32> text {};
    std::snprintf(text.data(), text.size(), "%.6g", fps);
    return text.data();
}

/// The last `lines` lines of a text file.
std::string tail(const std::string& path, int lines) {
    std::ifstream in(path);
    std::vector<std::string> kept;
    std::string line;
    while (std::getline(in, line)) {
        kept.push_back(line);
        if (static_cast<int>(kept.size()) > lines) {
            kept.erase(kept.begin());
        }
    }
    std::string out;
    for (const std::string& l : kept) {
        out += "\n  ffmpeg: " + l;
    }
    return out;
}

std::string describe_status(int status) {
    if (WIFEXITED(status)) {
        return "exited with status " + std::to_string(WEXITSTATUS(status));
    }
    if (WIFSIGNALED(status)) {
        return "was killed by signal " + std::to_string(WTERMSIG(status));
    }
    return "stopped";
}

} // namespace

std::string find_executable(const std::string& name) {
    if (name.empty()) {
        return {};
    }
    if (name.find('/') != std::string::npos) {
        return is_executable(name) ? name : std::string();
    }
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
        if (is_executable(candidate)) {
            return candidate;
        }
    }
    return {};
}

bool ffmpeg_has_libx264(const std::string& ffmpeg_path) {
    const std::string command = "'" + ffmpeg_path + "' -hide_banner -encoders 2>/dev/null";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) {
        return false;
    }
    std::array<char, 512> line {};
    bool found = false;
    while (std::fgets(line.data(), static_cast<int>(line.size()), pipe) != nullptr) {
        if (std::strstr(line.data(), " libx264 ") != nullptr) {
            found = true;
        }
    }
    ::pclose(pipe);
    return found;
}

FfmpegPipe::FfmpegPipe(const Mp4Options& options)
    : m_options(options) {
    if (options.width <= 0 || options.height <= 0 || options.width % 2 != 0
        || options.height % 2 != 0) {
        throw InputError("--size",
            "an mp4 (yuv420p) needs an even, positive width and height, got "
                + std::to_string(options.width) + "x" + std::to_string(options.height));
    }
    if (!(options.fps > 0 && options.fps <= 1000)) {
        throw InputError("--fps", "frames per second must be in (0, 1000]");
    }
    std::string name = options.ffmpeg;
    if (name.empty()) {
        const char* env = std::getenv("POLYCUT_FFMPEG");
        name = env != nullptr && *env != '\0' ? env : "ffmpeg";
    }
    const std::string exe = find_executable(name);
    if (exe.empty()) {
        throw Error("ffmpeg",
            "'" + name
                + "' was not found (PATH or POLYCUT_FFMPEG); install it (Debian: apt-get "
                  "install ffmpeg) or record PNG files with --png-dir instead of --mp4");
    }
    m_codec = ffmpeg_has_libx264(exe) ? "libx264" : "mpeg4";

    // SIGPIPE would kill the recorder when ffmpeg dies; ignore it and get EPIPE from write().
    std::signal(SIGPIPE, SIG_IGN);

    char log_template[] = "/tmp/polycut-ffmpeg-XXXXXX";
    const int log_fd = ::mkstemp(log_template);
    if (log_fd < 0) {
        throw Error("ffmpeg", std::string("cannot create a log file: ") + std::strerror(errno));
    }
    m_log_path = log_template;

    const std::string size = std::to_string(options.width) + "x" + std::to_string(options.height);
    const std::string fps = format_fps(options.fps);
    std::vector<std::string> args = { exe, "-hide_banner", "-nostdin", "-loglevel", "error", "-y",
        "-f", "rawvideo", "-pix_fmt", "rgba", "-s", size, "-r", fps, "-i", "-", "-an" };
    if (m_codec == "libx264") {
        args.insert(args.end(),
            { "-c:v", "libx264", "-preset", "veryfast", "-crf", std::to_string(options.crf),
                "-tune", "animation" });
    } else {
        args.insert(args.end(), { "-c:v", "mpeg4", "-q:v", "3" });
    }
    args.insert(args.end(), { "-pix_fmt", "yuv420p", "-movflags", "+faststart", options.path });

    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        ::close(log_fd);
        throw Error("ffmpeg", std::string("pipe: ") + std::strerror(errno));
    }
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        ::close(log_fd);
        throw Error("ffmpeg", std::string("fork: ") + std::strerror(errno));
    }
    if (pid == 0) {
        // Child: stdin from the pipe, stdout and stderr to the log. Only async-signal-safe calls.
        ::dup2(fds[0], STDIN_FILENO);
        ::dup2(log_fd, STDOUT_FILENO);
        ::dup2(log_fd, STDERR_FILENO);
        ::signal(SIGPIPE, SIG_DFL);
        ::execv(argv[0], argv.data());
        static const char kMessage[] = "exec failed\n";
        [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
        ::_exit(127);
    }
    ::close(fds[0]);
    ::close(log_fd);
    m_pid = pid;
    m_fd = fds[1];
}

FfmpegPipe::~FfmpegPipe() {
    if (m_fd >= 0) {
        ::close(m_fd);
        m_fd = -1;
    }
    if (m_pid > 0) {
        // Unfinished (an exception unwound past finish()): stop the encode, reap the child.
        ::kill(m_pid, SIGTERM);
        int status = 0;
        ::waitpid(m_pid, &status, 0);
        m_pid = -1;
    }
    if (!m_log_path.empty()) {
        ::unlink(m_log_path.c_str());
    }
}

std::string FfmpegPipe::failure(const std::string& what) {
    std::string message = what;
    if (m_fd >= 0) {
        ::close(m_fd);
        m_fd = -1;
    }
    if (m_pid > 0) {
        int status = 0;
        ::waitpid(m_pid, &status, 0);
        m_pid = -1;
        message += ": ffmpeg " + describe_status(status);
    }
    return message + tail(m_log_path, 6);
}

void FfmpegPipe::write(std::span<const std::uint8_t> rgba) {
    const std::size_t expected = static_cast<std::size_t>(m_options.width)
        * static_cast<std::size_t>(m_options.height) * 4;
    if (rgba.size() != expected) {
        throw InputError("frame",
            "frame has " + std::to_string(rgba.size()) + " bytes, expected "
                + std::to_string(expected));
    }
    if (m_fd < 0) {
        throw Error("ffmpeg", "the encode is already finished");
    }
    std::size_t done = 0;
    while (done < rgba.size()) {
        const ssize_t n = ::write(m_fd, rgba.data() + done, rgba.size() - done);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            const std::string reason = std::strerror(errno);
            throw Error("ffmpeg",
                failure("writing frame " + std::to_string(m_frames) + " to " + m_options.path
                    + " failed (" + reason + ")"));
        }
        done += static_cast<std::size_t>(n);
    }
    ++m_frames;
}

void FfmpegPipe::finish() {
    if (m_pid <= 0) {
        return;
    }
    ::close(m_fd);
    m_fd = -1;
    int status = 0;
    while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR) { }
    m_pid = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        const std::string message = "encoding " + m_options.path + " failed: ffmpeg "
            + describe_status(status) + tail(m_log_path, 6);
        throw Error("ffmpeg", message);
    }
}

} // namespace polycut::record
