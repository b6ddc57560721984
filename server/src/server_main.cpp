// polycut-server: the real-time cutting server (docs/protocol.md).
//   polycut-server [--scene FILE] [--control EP] [--stream EP] [--rate HZ] [--scene-dir DIR]
//                  [--record-commands FILE] [--scene-memory MB] [--curve-keys DIR | --insecure]
//                  [--paused] [--quiet]
//   polycut-server --curve-keygen DIR
//   polycut-server --replay LOG [--scene-dir DIR] [--until-tick N] [--trace]
// Prints one JSON line on stdout once both sockets are bound ({"control", "stream", ...}; ports
// are resolved when an endpoint ends in ":*"), then logs one stats line per second on stderr.
// SIGINT/SIGTERM stop it cleanly. --replay plays a command log on a fresh simulation and prints
// the final state as one JSON line (determinism checks, offline rendering); --trace also prints
// one JSON line per replayed tick on stderr (step, assembly, solve and cut ms, PCG iterations).
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "server.hpp"
#include "server_command_log.hpp"
#include "server_curve.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace {

polycut::server::Server* g_server = nullptr;
std::atomic<int> g_signal { 0 };

extern "C" void on_signal(int sig) {
    g_signal.store(sig);
    if (g_server != nullptr) {
        g_server->request_stop();
    }
}

/// Ends the process when a signal's stop request is not honoured within one tick (at least
/// 100 ms): the loop checks its stop flag between messages and ticks and at least every 50 ms
/// while it waits, but one long command (a scene build, a large cut) cannot be interrupted.
/// Exit status 128 + signal, as a shell reports it.
class Watchdog {
public:
    explicit Watchdog(double rate_hz)
        : m_grace(std::chrono::duration<double>(std::max(1.0 / rate_hz, 0.1)))
        , m_thread([this] { watch(); }) { }
    ~Watchdog() {
        m_done.store(true);
        m_thread.join();
    }

private:
    void watch() {
        while (!m_done.load()) {
            if (const int sig = g_signal.load(); sig != 0) {
                const auto deadline = std::chrono::steady_clock::now() + m_grace;
                while (!m_done.load() && std::chrono::steady_clock::now() < deadline) {
                    std::this_thread::sleep_for(std::chrono::milliseconds(2));
                }
                if (!m_done.load()) {
                    std::fprintf(stderr,
                        "[warn] polycut-server: stopping on signal %d during long work\n", sig);
                    std::_Exit(128 + sig);
                }
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
    std::chrono::duration<double> m_grace;
    std::atomic<bool> m_done { false };
    std::thread m_thread;
};

int usage(const std::string& why) {
    std::fprintf(stderr,
        "polycut-server: %s\n"
        "usage: polycut-server [--scene FILE] [--control EP] [--stream EP] [--rate HZ]\n"
        "                      [--scene-dir DIR] [--record-commands FILE] [--scene-memory MB]\n"
        "                      [--curve-keys DIR | --insecure] [--paused] [--quiet]\n"
        "       polycut-server --replay LOG [--scene-dir DIR] [--until-tick N] [--trace]\n"
        "       polycut-server --curve-keygen DIR\n"
        "defaults: --control tcp://127.0.0.1:5555 --stream tcp://127.0.0.1:5556 --rate 60\n",
        why.c_str());
    return 2;
}

bool parse_double(const char* text, double& out) {
    char* end = nullptr;
    out = std::strtod(text, &end);
    return end != text && *end == '\0';
}

std::string hex64(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

int replay(const std::string& log, const std::string& scene_dir, long until_tick, bool trace) {
    polycut::server::SessionConfig config;
    if (!scene_dir.empty()) {
        config.scene_dir = scene_dir;
    }
    polycut::server::Session session(config);
    std::optional<std::int64_t> until;
    if (until_tick >= 0) {
        until = until_tick;
    }
    // Step figures of the replay, to compare with the live server's (a live step much slower
    // than the replayed one at the same work is CPU contention, not simulation work).
    std::vector<double> step_ms, cpu_ms, iterations;
    double cut_ms = 0.0, worst_cut_ms = 0.0;
    double cpu_before = polycut::thread_cpu_ms();
    const auto summary = polycut::server::replay_command_log(
        log, session,
        [&](const polycut::server::Session&, const polycut::sim::StepReport& report) {
            const double cpu = polycut::thread_cpu_ms();
            step_ms.push_back(report.step_ms);
            cpu_ms.push_back(cpu - cpu_before); // includes the commands applied before the tick
            cpu_before = cpu;
            iterations.push_back(report.solver_iterations);
            const double cut = report.cut_ms;
            cut_ms += cut;
            worst_cut_ms = std::max(worst_cut_ms, cut);
            if (trace) {
                std::cerr << nlohmann::json {
                    { "tick", report.tick }, { "step_ms", report.step_ms },
                    { "assembly_ms", report.assembly_ms }, { "solve_ms", report.solve_ms },
                    { "cut_ms", report.cut_ms }, { "iterations", report.solver_iterations },
                    { "topology_changed", report.topology_changed }
                }.dump() << "\n";
            }
        },
        until);
    auto figures = [](const std::vector<double>& v) {
        if (v.empty()) {
            return nlohmann::json(nullptr);
        }
        return nlohmann::json { { "p50", polycut::percentile(v, 50.0) },
            { "p99", polycut::percentile(v, 99.0) },
            { "max", *std::max_element(v.begin(), v.end()) } };
    };
    const polycut::sim::CutAreas areas = session.simulation().cut_areas();
    const nlohmann::json out = { { "tick", summary.tick }, { "commands", summary.commands },
        { "rejected", summary.rejected }, { "state_hash", hex64(summary.state_hash) },
        { "topology_version", summary.topology_version }, { "scene", summary.scene },
        { "step_ms", figures(step_ms) }, { "tick_cpu_ms", figures(cpu_ms) },
        { "solver_iterations", figures(iterations) }, { "cut_ms_total", cut_ms },
        { "cut_ms_max", worst_cut_ms },
        // As get_stats reports them (rest space, issue 12 item 4), at the last tick.
        { "cut_area", areas.cut_area }, { "swept_area", areas.swept_area },
        { "swept_area_undone", areas.swept_area_undone },
        { "cut_completeness", areas.completeness() } };
    std::cout << out.dump() << std::endl;
    return summary.rejected == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    using polycut::server::ServerConfig;
    ServerConfig config;
    std::string replay_log;
    long until_tick = -1;
    bool trace = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (a == "--paused") {
            config.paused = true;
        } else if (a == "--insecure") {
            config.insecure = true;
        } else if (a == "--trace") {
            trace = true;
        } else if (a == "--quiet") {
            config.log_stats = false;
        } else if (a == "--help" || a == "-h") {
            usage("help");
            return 0;
        } else if ((v = value()) == nullptr) {
            return usage("unknown option or missing value: " + a);
        } else if (a == "--scene") {
            config.scene_file = v;
        } else if (a == "--control") {
            config.control = v;
        } else if (a == "--stream") {
            config.stream = v;
        } else if (a == "--scene-dir") {
            config.scene_dir = v;
        } else if (a == "--record-commands") {
            config.record_commands = v;
        } else if (a == "--replay") {
            replay_log = v;
        } else if (a == "--until-tick") {
            double t = 0;
            if (!parse_double(v, t) || t < 0) {
                return usage("--until-tick needs a non-negative integer");
            }
            until_tick = static_cast<long>(t);
        } else if (a == "--curve-keys") {
            config.curve_keys = v;
        } else if (a == "--curve-keygen") {
            const auto client = polycut::server::write_curve_keys(v);
            std::cout << nlohmann::json { { "dir", v }, { "client_public", client.first } }.dump()
                      << std::endl;
            return 0;
        } else if (a == "--scene-memory") {
            double mb = 0;
            if (!parse_double(v, mb) || !(mb > 0) || mb > 1e9) {
                return usage("--scene-memory needs a size in MB > 0");
            }
            config.limits.max_scene_bytes = std::uint64_t(mb * 1e6);
        } else if (a == "--rate") {
            if (!parse_double(v, config.rate_hz)) {
                return usage("--rate needs a number [Hz]");
            }
        } else {
            return usage("unknown option " + a);
        }
    }
    try {
        if (!replay_log.empty()) {
            return replay(replay_log, config.scene_dir, until_tick, trace);
        }
        polycut::server::Server server(config);
        const nlohmann::json ready = { { "control", server.control_endpoint() },
            { "stream", server.stream_endpoint() }, { "rate_hz", config.rate_hz },
            { "scene", config.scene_file ? nlohmann::json(*config.scene_file) : nullptr },
            { "paused", config.paused } };
        std::cout << ready.dump() << std::endl;
        g_server = &server;
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        {
            const Watchdog watchdog(config.rate_hz);
            server.run();
        }
        g_server = nullptr;
        if (server.scene_build_in_flight()) {
            // The loop stopped within a tick; the scene being built (a worker thread that
            // cannot be interrupted) is abandoned rather than waited for. The command log is
            // complete: run() wrote its end marker.
            std::fprintf(stderr, "[info] polycut-server: stopped (a scene build was abandoned)\n");
            std::fflush(nullptr);
            std::_Exit(0);
        }
        std::fprintf(stderr, "[info] polycut-server: stopped\n");
        return 0;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-server: %s: %s\n", e.where().c_str(), e.problem().c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-server: %s\n", e.what());
        return 2;
    }
}
