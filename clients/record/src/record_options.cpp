// polycut-record command line (see record_options.hpp).
#include "record_options.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <cstdlib>

namespace polycut::record {

namespace {

double to_number(const std::string& option, const std::string& text) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
        throw InputError(option, "needs a number, got '" + text + "'");
    }
    return value;
}

long to_count(const std::string& option, const std::string& text, long min) {
    const double value = to_number(option, text);
    if (value != std::floor(value) || value < double(min) || value > 1e9) {
        throw InputError(
            option, "needs an integer >= " + std::to_string(min) + ", got '" + text + "'");
    }
    return static_cast<long>(value);
}

} // namespace

std::string record_usage() {
    return "usage: polycut-record [--server EP] [--stream EP] [--every K] [--frames N | --seconds "
           "S]\n"
           "                      (--png-dir DIR | --mp4 FILE) [--size WxH] [--msaa N] [--fps F]\n"
           "                      [--stills DIR] [--still-every N] [--timeout S] [--nice N] "
           "[--quiet]\n"
           "                      [--two-sided]\n"
           "       polycut-record --offline SCENE.json [--commands LOG] [--scene-dir DIR]\n"
           "                      [--every K] [--frames N] (--png-dir DIR | --mp4 FILE) ...\n"
           "                      [--vtu DIR]  (volume mesh per frame + DIR/series.pvd; may be\n"
           "                      the only output)\n"
           "Live: subscribes to a running polycut-server and renders every K-th stream frame\n"
           "until N frames, S seconds or Ctrl-C. Offline: replays a command log written by\n"
           "polycut-server --record-commands and renders every K-th tick, deterministically.\n"
           "defaults: --server tcp://127.0.0.1:5555 --size 640x480 --msaa 4 --every 1 --timeout "
           "10\n"
           "          --fps = tick rate / K (live: from hello; offline: 1 / (scene dt))\n";
}

RecordCommand parse_record_command(const std::vector<std::string>& args) {
    RecordCommand command;
    bool has_frames = false;
    bool has_seconds = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            command.help = true;
            return command;
        }
        if (a == "--quiet") {
            command.quiet = true;
            continue;
        }
        if (a == "--two-sided") {
            command.render.cull_back_faces = false;
            continue;
        }
        if (i + 1 >= args.size()) {
            throw InputError(a,
                a.rfind("--", 0) == 0 ? "unknown option or missing value" : "unexpected argument");
        }
        const std::string& v = args[++i];
        if (a == "--server") {
            command.live.server = v;
        } else if (a == "--stream") {
            command.live.stream = v;
        } else if (a == "--every") {
            command.live.every = command.offline_options.every = to_count(a, v, 1);
        } else if (a == "--frames") {
            command.live.max_frames = command.offline_options.max_frames = to_count(a, v, 1);
            has_frames = true;
        } else if (a == "--seconds") {
            command.live.seconds = to_number(a, v);
            if (command.live.seconds <= 0) {
                throw InputError(a, "must be > 0");
            }
            has_seconds = true;
        } else if (a == "--png-dir") {
            command.png_dir = v;
        } else if (a == "--mp4") {
            command.mp4 = v;
        } else if (a == "--size") {
            const auto x = v.find('x');
            if (x == std::string::npos) {
                throw InputError(a, "needs WIDTHxHEIGHT, e.g. 640x480");
            }
            command.render.width = static_cast<int>(to_count(a, v.substr(0, x), 1));
            command.render.height = static_cast<int>(to_count(a, v.substr(x + 1), 1));
        } else if (a == "--msaa") {
            command.render.msaa = static_cast<int>(to_count(a, v, 0));
        } else if (a == "--fps") {
            command.fps = to_number(a, v);
            if (*command.fps <= 0 || *command.fps > 1000) {
                throw InputError(a, "must be in (0, 1000]");
            }
        } else if (a == "--stills") {
            command.render.stills_dir = v;
        } else if (a == "--still-every") {
            command.render.still_every = to_count(a, v, 1);
        } else if (a == "--nice") {
            command.nice = static_cast<int>(to_count(a, v, 0));
            if (command.nice > 19) {
                throw InputError(a, "must be in [0, 19]");
            }
        } else if (a == "--timeout") {
            command.live.reply_timeout_s = to_number(a, v);
            if (command.live.reply_timeout_s <= 0) {
                throw InputError(a, "must be > 0");
            }
        } else if (a == "--offline") {
            command.offline = true;
            command.offline_options.scene_file = v;
        } else if (a == "--commands") {
            command.offline_options.commands = v;
        } else if (a == "--vtu") {
            command.offline_options.vtu_dir = v;
        } else if (a == "--scene-dir") {
            command.offline_options.scene_dir = v;
        } else {
            throw InputError(a, "unknown option");
        }
    }
    if (!command.offline_options.vtu_dir.empty() && !command.offline) {
        throw InputError("--vtu",
            "only with --offline SCENE.json (the volume mesh is not on the stream; record the "
            "session's commands and replay them)");
    }
    const bool vtu_only = !command.offline_options.vtu_dir.empty() && command.png_dir.empty()
        && command.mp4.empty();
    if (!vtu_only && command.png_dir.empty() == command.mp4.empty()) {
        throw InputError("--png-dir", "give exactly one of --png-dir DIR or --mp4 FILE");
    }
    if (has_frames && has_seconds) {
        throw InputError("--seconds", "give --frames or --seconds, not both");
    }
    if (command.offline && has_seconds) {
        throw InputError("--seconds", "offline recordings stop at the log's end or at --frames");
    }
    if (!command.offline && !command.offline_options.commands.empty()) {
        throw InputError("--commands", "only with --offline SCENE.json");
    }
    command.offline_options.progress = !command.quiet;
    return command;
}

} // namespace polycut::record
