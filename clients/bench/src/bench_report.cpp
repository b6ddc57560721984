// Benchmark report (see bench_report.hpp).
#include "bench_report.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <thread>

extern char** environ;

namespace polycut::bench {

namespace {

using json = nlohmann::json;

double round3(double v) {
    return std::round(v * 1000.0) / 1000.0;
}

json rounded(const std::vector<double>& sample) {
    json out = json::array();
    for (const double v : sample) {
        out.push_back(round3(v));
    }
    return out;
}

json distribution(const std::vector<double>& sample) {
    const Summary s = summarize(sample);
    return { { "count", s.count }, { "p50", round3(s.median) }, { "p95", round3(s.p95) },
        { "p99", round3(s.p99) }, { "max", round3(s.max) }, { "mean", round3(s.mean) } };
}

std::string command_name(ProbeCommand c) {
    switch (c) {
    case ProbeCommand::ApplyForce:
        return "apply_force";
    case ProbeCommand::Scalpel:
        return "scalpel";
    case ProbeCommand::Cut:
        return "cut";
    }
    return "?";
}

} // namespace

std::string machine_json() {
    json m;
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            m["cpu"] = colon == std::string::npos ? line : line.substr(colon + 2);
            break;
        }
    }
    m["logical_cpus"] = std::thread::hardware_concurrency();
    utsname u {};
    if (::uname(&u) == 0) {
        m["kernel"] = std::string(u.sysname) + " " + u.release;
        m["host"] = u.nodename;
    }
    std::ifstream loadavg("/proc/loadavg");
    double l1 = 0;
    if (loadavg >> l1) {
        m["load_average_1min"] = l1;
    }
    return m.dump();
}

std::string report_json(const ProbeOptions& options, const ProbeResult& r) {
    json out;
    out["machine"] = json::parse(machine_json());
    out["config"] = { { "server", options.server }, { "duration_s", options.duration_s },
        { "command", command_name(options.command) },
        { "command_rate_hz", options.command_rate_hz }, { "rtt_rate_hz", options.rtt_rate_hz },
        { "subscribers", options.subscribers }, { "scene", r.scene },
        { "vertex_count", r.vertex_count }, { "triangle_count", r.triangle_count } };
    out["control_rtt_ms"] = distribution(r.control_rtt_ms);
    out["command_ack_ms"] = distribution(r.command_ack_ms);
    out["command_to_visible_ms"] = distribution(r.visible_ms);
    out["command_to_visible_ticks"] = distribution(r.visible_ticks);
    out["server"] = { { "rate_hz", r.rate_hz }, { "tick_budget_ms", round3(1000.0 / r.rate_hz) },
        { "step_ms", distribution(r.step_ms) },
        { "frame_interval_ms", distribution(r.frame_interval_ms) }, { "ticks", r.ticks },
        { "ticks_over_budget", r.ticks_over_budget }, { "worst_tick_ms", round3(r.worst_tick_ms) },
        { "stats_step_ms_p50", round3(r.stats_step_ms_p50) },
        { "stats_step_ms_p99", round3(r.stats_step_ms_p99) },
        { "stream_dropped", r.stream_dropped } };
    out["stream"] = { { "frames", r.frames }, { "gaps", r.gaps },
        { "extra_subscriber_frames", r.extra_frames } };
    out["commands"] = { { "sent", r.commands_sent }, { "visible", r.commands_visible },
        { "errors", r.command_errors },
        { "not_visible", r.commands_sent - r.commands_visible - r.command_errors } };
    out["wall_s"] = round3(r.wall_s);
    out["samples"] = { { "command_to_visible_ms", rounded(r.visible_ms) },
        { "control_rtt_ms", rounded(r.control_rtt_ms) }, { "server_step_ms", rounded(r.step_ms) } };
    return out.dump();
}

std::string report_text(const ProbeResult& r) {
    const Summary visible = summarize(r.visible_ms);
    const Summary ticks = summarize(r.visible_ticks);
    const Summary rtt = summarize(r.control_rtt_ms);
    const Summary step = summarize(r.step_ms);
    char text[1024];
    std::snprintf(text, sizeof text,
        "command to visible: p50 %.1f ms, p99 %.1f ms, max %.1f ms (p50 %.0f, max %.0f ticks at "
        "%.0f Hz; %ld of %ld commands seen)\n"
        "control round trip: p50 %.2f ms, p99 %.2f ms\n"
        "server step:        p50 %.2f ms, p99 %.2f ms; %llu of %lld ticks over the %.1f ms "
        "budget\n",
        visible.median, visible.p99, visible.max, ticks.median, ticks.max, r.rate_hz,
        r.commands_visible, r.commands_sent, rtt.median, rtt.p99, step.median, step.p99,
        static_cast<unsigned long long>(r.ticks_over_budget), static_cast<long long>(r.ticks),
        r.rate_hz > 0 ? 1000.0 / r.rate_hz : 0.0);
    return text;
}

void plot_histograms(
    const std::string& script, const std::string& report_path, const std::string& png_path) {
    const std::string python = "/usr/bin/python3";
    std::vector<std::string> args { python, script, report_path, png_path };
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = ::posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
    if (spawned != 0) {
        throw FileError(python, 0, "cannot run the histogram script " + script);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) { }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        throw FileError(png_path, 0,
            "the histogram script " + script + " failed (exit status "
                + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    }
}

} // namespace polycut::bench
