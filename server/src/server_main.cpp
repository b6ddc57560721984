// polycut-server: the real-time cutting server (docs/protocol.md).
//   polycut-server [--scene FILE] [--control EP] [--stream EP] [--rate HZ] [--scene-dir DIR]
//                  [--record-commands FILE] [--paused] [--quiet]
//   polycut-server --replay LOG [--scene-dir DIR] [--until-tick N]
// Prints one JSON line on stdout once both sockets are bound ({"control", "stream", ...}; ports
// are resolved when an endpoint ends in ":*"), then logs one stats line per second on stderr.
// SIGINT/SIGTERM stop it cleanly. --replay plays a command log on a fresh simulation and prints
// the final state as one JSON line (determinism checks, offline rendering).
#include "polycut/common/error.hpp"
#include "server.hpp"
#include "server_command_log.hpp"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

polycut::server::Server* g_server = nullptr;

extern "C" void on_signal(int) {
    if (g_server != nullptr) {
        g_server->request_stop();
    }
}

int usage(const std::string& why) {
    std::fprintf(stderr,
        "polycut-server: %s\n"
        "usage: polycut-server [--scene FILE] [--control EP] [--stream EP] [--rate HZ]\n"
        "                      [--scene-dir DIR] [--record-commands FILE] [--paused] [--quiet]\n"
        "       polycut-server --replay LOG [--scene-dir DIR] [--until-tick N]\n"
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

int replay(const std::string& log, const std::string& scene_dir, long until_tick) {
    polycut::server::SessionConfig config;
    if (!scene_dir.empty()) {
        config.scene_dir = scene_dir;
    }
    polycut::server::Session session(config);
    std::optional<std::int64_t> until;
    if (until_tick >= 0) {
        until = until_tick;
    }
    const auto summary = polycut::server::replay_command_log(log, session, {}, until);
    const nlohmann::json out = { { "tick", summary.tick }, { "commands", summary.commands },
        { "rejected", summary.rejected }, { "state_hash", hex64(summary.state_hash) },
        { "topology_version", summary.topology_version }, { "scene", summary.scene } };
    std::cout << out.dump() << std::endl;
    return summary.rejected == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    using polycut::server::ServerConfig;
    ServerConfig config;
    std::string replay_log;
    long until_tick = -1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = nullptr;
        if (a == "--paused") {
            config.paused = true;
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
            return replay(replay_log, config.scene_dir, until_tick);
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
        server.run();
        g_server = nullptr;
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
