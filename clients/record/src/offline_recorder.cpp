// Offline recording by command-log replay (see offline_recorder.hpp).
#include "offline_recorder.hpp"

#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/mesh/io_pvd.hpp"
#include "progress_bar.hpp"
#include "server_command_log.hpp"
#include "server_session.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <unistd.h>

namespace polycut::record {

namespace {

using json = nlohmann::json;

/// The log's header and how far it goes.
struct LogInfo {
    json header = json::object();
    std::int64_t last_tick = 0; ///< end marker's tick, else the last command's
    bool has_end = false; ///< the log has an end marker
    std::vector<std::string> body; ///< every line after the header
};

LogInfo read_log(const std::string& path) {
    LogInfo info;
    if (path.empty()) {
        info.header = { { "polycut_command_log", 1 } };
        return info;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw FileError(path, 0, "cannot open the command log");
    }
    std::string line;
    long line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (line.empty()) {
            continue;
        }
        json record;
        try {
            record = json::parse(line);
        } catch (const json::exception& e) {
            throw FileError(path, line_no, std::string("not JSON: ") + e.what());
        }
        if (line_no == 1) {
            if (!record.is_object() || !record.contains("polycut_command_log")) {
                throw FileError(path, 1, "not a polycut command log (no header line)");
            }
            info.header = std::move(record);
            continue;
        }
        if (record.is_object() && record.contains("tick") && record["tick"].is_number_integer()) {
            info.last_tick = std::max(info.last_tick, record["tick"].get<std::int64_t>());
            info.has_end = info.has_end || record.value("end", false);
        }
        info.body.push_back(line);
    }
    if (line_no == 0) {
        throw FileError(path, 0, "empty command log");
    }
    return info;
}

/// A temporary file removed on destruction.
class TempFile {
public:
    TempFile() {
        char name[] = "/tmp/polycut-replay-XXXXXX";
        const int fd = ::mkstemp(name);
        if (fd < 0) {
            throw FileError(name, 0, "cannot create a temporary file");
        }
        ::close(fd);
        m_path = name;
    }
    ~TempFile() { std::remove(m_path.c_str()); }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    const std::string& path() const { return m_path; }

private:
    std::string m_path;
};

std::string hex64(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

std::optional<render::Camera> scene_camera(const scene::Scene& scene) {
    if (scene.camera.automatic) {
        return std::nullopt;
    }
    render::Camera camera;
    camera.position = scene.camera.position;
    camera.target = scene.camera.target;
    camera.up = scene.camera.up;
    camera.fov_y_deg = scene.camera.fov_deg;
    const double distance = (camera.position - camera.target).norm();
    camera.near = std::max(1e-4, distance * 0.01);
    camera.far = std::max(camera.near * 10, distance * 10);
    return camera;
}

} // namespace

bool offline_available() {
    return true;
}

OfflineSummary record_offline(
    const OfflineOptions& options, const RecordRender& render, const SinkFactory& make_sink) {
    if (options.every < 1) {
        throw InputError("--every", "must be >= 1");
    }
    if (options.max_frames < 0) {
        throw InputError("--frames", "must be >= 0");
    }
    if (options.scene_file.empty() || !std::filesystem::is_regular_file(options.scene_file)) {
        throw FileError(options.scene_file, 0, "scene file not found");
    }
    const Stopwatch wall;
    LogInfo log = read_log(options.commands);
    if (options.max_frames == 0 && log.last_tick == 0) {
        throw InputError("--frames",
            "the command log has no ticks to replay; give --frames N to render N ticks");
    }

    // The replay reads the scene from the log header: point it at the requested scene file.
    TempFile replay_log;
    {
        json header = log.header;
        header["scene_file"] = std::filesystem::absolute(options.scene_file).string();
        std::ofstream out(replay_log.path(), std::ios::binary);
        out << header.dump() << '\n';
        for (const std::string& line : log.body) {
            out << line << '\n';
        }
        if (!out) {
            throw FileError(replay_log.path(), 0, "cannot write the replay log");
        }
    }

    server::SessionConfig config;
    if (!options.scene_dir.empty()) {
        config.scene_dir = options.scene_dir;
    } else if (log.header.contains("scene_dir") && log.header["scene_dir"].is_string()) {
        config.scene_dir = log.header["scene_dir"].get<std::string>();
    }
    server::Session session(config);

    std::optional<std::int64_t> until;
    std::int64_t total = log.last_tick;
    if (options.max_frames > 0) {
        until = 1 + (options.max_frames - 1) * options.every;
        // The replay stops at the end marker or at `until`, whichever comes first.
        if (!log.has_end || *until < log.last_tick) {
            total = *until;
        }
    }

    OfflineSummary summary;
    std::optional<FrameRecorder> recorder;
    bool sink_made = false;
    std::optional<mesh::PvdCollection> series;
    if (!options.vtu_dir.empty()) {
        std::filesystem::create_directories(options.vtu_dir);
        series.emplace(options.vtu_dir + "/series.pvd");
    }
    ProgressBar progress(static_cast<long>(total), "polycut-record", "ticks", options.progress);
    double step_ms = 0;
    const auto on_tick = [&](const server::Session& s, const sim::StepReport& report) {
        ++summary.ticks;
        step_ms += report.step_ms;
        const std::int64_t tick = s.tick();
        progress.update(static_cast<long>(std::min<std::int64_t>(summary.ticks, total)));
        if ((tick - 1) % options.every != 0) {
            return;
        }
        if (options.max_frames > 0 && summary.frames >= options.max_frames) {
            return;
        }
        ++summary.frames;
        if (series) {
            char name[64];
            std::snprintf(name, sizeof name, "frame_%06lld.vtu", static_cast<long long>(tick));
            s.simulation().write_vtu(options.vtu_dir + "/" + name);
            series->add(s.simulation().time(), name);
        }
        if (!sink_made) {
            sink_made = true;
            const double dt = s.simulation().scene().integrator.dt;
            summary.fps = dt > 0 ? std::round(1000.0 / (dt * double(options.every))) / 1000.0
                                 : 60.0 / double(options.every);
            RecordRender settings = render;
            if (!settings.camera) {
                settings.camera = scene_camera(s.simulation().scene());
            }
            if (auto sink = make_sink(summary.fps)) {
                recorder.emplace(settings, std::move(sink));
            }
        }
        if (!recorder) {
            return;
        }
        const sim::Surface surface = s.simulation().surface();
        render::SurfaceArrays arrays;
        arrays.positions = surface.positions;
        arrays.triangles = surface.triangles;
        arrays.tags = surface.tags;
        // The tools where they were during this tick (issue 15: the videos show the probe
        // pressing the tissue).
        std::vector<render::Tool> tools;
        for (const auto& [id, spec] : s.simulation().tools()) {
            render::Tool t;
            t.position = spec.pose.position;
            t.rotation = spec.pose.orientation.normalized().toRotationMatrix();
            t.radius = spec.radius;
            t.length = spec.length;
            t.size = spec.size;
            t.kind = spec.kind == sim::ToolSpec::Kind::Sphere ? render::Tool::Kind::Sphere
                : spec.kind == sim::ToolSpec::Kind::Capsule   ? render::Tool::Kind::Capsule
                                                              : render::Tool::Kind::Box;
            tools.push_back(t);
        }
        recorder->add(arrays, tools);
    };
    const server::ReplaySummary replay
        = server::replay_command_log(replay_log.path(), session, on_tick, until);
    progress.finish();
    if (summary.frames == 0) {
        throw InputError("--commands", "the replay recorded no frame");
    }
    if (recorder) {
        recorder->finish();
    }
    summary.commands = replay.commands;
    summary.rejected = replay.rejected;
    summary.state_hash = hex64(replay.state_hash);
    summary.topology_version = replay.topology_version;
    summary.wall_s = wall.ms() / 1000.0;
    summary.step_ms_mean = summary.ticks > 0 ? step_ms / double(summary.ticks) : 0.0;
    summary.render_ms_mean
        = recorder && summary.frames > 0 ? recorder->busy_ms() / double(summary.frames) : 0.0;
    return summary;
}

} // namespace polycut::record
