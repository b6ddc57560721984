// polycut-record: renders a cutting session to PNG files or an mp4, live from a running
// polycut-server's stream or offline from a command log (docs/recording.md). Prints one JSON
// summary line on stdout; messages and the progress bar go to stderr.
#include "polycut/common/error.hpp"
#include "record_options.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sys/resource.h>

namespace {

std::atomic<bool> g_stop { false };

extern "C" void on_signal(int) {
    g_stop.store(true);
}

using polycut::record::RecordCommand;

polycut::record::SinkFactory sink_factory(const RecordCommand& command) {
    return [&command](double fps) -> std::unique_ptr<polycut::record::FrameSink> {
        if (command.png_dir.empty() && command.mp4.empty()) {
            return nullptr; // --vtu only
        }
        if (!command.png_dir.empty()) {
            return polycut::record::make_png_sink(command.png_dir);
        }
        polycut::record::Mp4Options mp4;
        mp4.path = command.mp4;
        mp4.width = command.render.width;
        mp4.height = command.render.height;
        mp4.fps = command.fps.value_or(fps);
        return polycut::record::make_mp4_sink(mp4);
    };
}

int run_live(const RecordCommand& command) {
    using namespace polycut::record;
    std::signal(SIGINT, on_signal); // stop receiving, render what is queued, finish the mp4
    std::signal(SIGTERM, on_signal);
    const ServerInfo server = query_server(command.live);
    const double fps = server.rate_hz / double(command.live.every);
    FrameRecorder recorder(command.render, sink_factory(command)(fps));
    if (!command.quiet) {
        std::fprintf(stderr, "polycut-record: recording %s to %s (Ctrl-C to stop)\n",
            server.stream.c_str(), recorder.describe().c_str());
    }
    const LiveSummary s = record_live(command.live, server, recorder, g_stop);
    const nlohmann::json out = { { "mode", "live" }, { "output", recorder.describe() },
        { "frames", s.rendered }, { "received", s.received }, { "gaps", s.gaps },
        { "snapshots", s.snapshots }, { "dropped", s.dropped }, { "first_tick", s.first_tick },
        { "last_tick", s.last_tick }, { "first_seq", s.first_seq }, { "last_seq", s.last_seq },
        { "fps", command.fps.value_or(fps) }, { "wall_s", s.wall_s },
        { "render_ms_mean", s.render_ms_mean } };
    std::cout << out.dump() << std::endl;
    return 0;
}

int run_offline(const RecordCommand& command) {
    using namespace polycut::record;
    const OfflineSummary s
        = record_offline(command.offline_options, command.render, sink_factory(command));
    const nlohmann::json out = { { "mode", "offline" },
        { "output",
            !command.png_dir.empty()
                ? command.png_dir
                : (!command.mp4.empty() ? command.mp4 : command.offline_options.vtu_dir) },
        { "frames", s.frames }, { "ticks", s.ticks }, { "commands", s.commands },
        { "rejected", s.rejected }, { "state_hash", s.state_hash },
        { "topology_version", s.topology_version }, { "fps", command.fps.value_or(s.fps) },
        { "wall_s", s.wall_s }, { "step_ms_mean", s.step_ms_mean },
        { "render_ms_mean", s.render_ms_mean } };
    std::cout << out.dump() << std::endl;
    return s.rejected == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    try {
        const RecordCommand command = polycut::record::parse_record_command(
            std::vector<std::string>(argv + 1, argv + argc));
        if (command.help) {
            std::cout << polycut::record::record_usage();
            return 0;
        }
        // Before any thread (llvmpipe's, the receiver) or ffmpeg starts: they inherit it.
        if (command.nice > 0 && ::setpriority(PRIO_PROCESS, 0, command.nice) != 0) {
            std::fprintf(
                stderr, "polycut-record: could not lower the priority (nice %d)\n", command.nice);
        }
        return command.offline ? run_offline(command) : run_live(command);
    } catch (const polycut::InputError& e) {
        std::fprintf(stderr, "polycut-record: %s: %s\n%s", e.where().c_str(), e.problem().c_str(),
            polycut::record::record_usage().c_str());
        return 2;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-record: %s: %s\n", e.where().c_str(), e.problem().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-record: %s\n", e.what());
        return 1;
    }
}
