// polycut-bench: the latency benchmark (docs/recording.md "Benchmark"). Prints the JSON report
// on stdout (and to --json FILE), and draws the histograms to --histogram FILE.png with
// clients/bench/plot_bench.py (matplotlib; POLYCUT_BENCH_PLOT overrides the script's path).
#include "bench_report.hpp"
#include "polycut/common/error.hpp"

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

namespace {

std::atomic<bool> g_stop { false };
extern "C" void on_signal(int) {
    g_stop.store(true);
}

const char* kUsage
    = "usage: polycut-bench [--server EP] [--stream EP] [--duration S] [--rate HZ]\n"
      "                     [--rtt-rate HZ] [--subscribers N] [--command apply_force|scalpel|cut]\n"
      "                     [--scene NAME] [--json OUT] [--histogram OUT.png] [--warmup S] "
      "[--quiet]\n"
      "Prints the JSON report on stdout and a short summary on stderr (not with --quiet).\n"
      "Measures control round trips (get_stats), command-to-visible latency (command sent ->\n"
      "first stream frame listing it in `applied`) and the server's tick times, under load.\n"
      "defaults: --server tcp://127.0.0.1:5555 --duration 10 --rate 20 --rtt-rate 20\n"
      "          --subscribers 0 --command apply_force\n";

double number(const std::string& option, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v)) {
        throw polycut::InputError(option, "needs a number, got '" + text + "'");
    }
    return v;
}

} // namespace

int main(int argc, char** argv) {
    using namespace polycut::bench;
    try {
        ProbeOptions options;
        std::string json_path, histogram_path;
        bool quiet = false;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--help" || a == "-h") {
                std::cout << kUsage;
                return 0;
            }
            if (a == "--quiet") {
                quiet = true;
                continue;
            }
            if (i + 1 >= argc) {
                throw polycut::InputError(a, "unknown option or missing value");
            }
            const std::string v = argv[++i];
            if (a == "--server") {
                options.server = v;
            } else if (a == "--stream") {
                options.stream = v;
            } else if (a == "--duration") {
                options.duration_s = number(a, v);
            } else if (a == "--warmup") {
                options.warmup_s = number(a, v);
            } else if (a == "--rate") {
                options.command_rate_hz = number(a, v);
            } else if (a == "--rtt-rate") {
                options.rtt_rate_hz = number(a, v);
            } else if (a == "--subscribers") {
                options.subscribers = static_cast<int>(number(a, v));
            } else if (a == "--scene") {
                options.scene = v;
            } else if (a == "--json") {
                json_path = v;
            } else if (a == "--histogram") {
                histogram_path = v;
            } else if (a == "--command") {
                if (v == "apply_force") {
                    options.command = ProbeCommand::ApplyForce;
                } else if (v == "scalpel") {
                    options.command = ProbeCommand::Scalpel;
                } else if (v == "cut") {
                    options.command = ProbeCommand::Cut;
                } else {
                    throw polycut::InputError(a, "one of apply_force, scalpel, cut");
                }
            } else {
                throw polycut::InputError(a, "unknown option");
            }
        }
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        const ProbeResult result = run_probe(options, g_stop);
        const std::string report = report_json(options, result);
        std::cout << report << std::endl;
        if (!quiet) {
            std::fprintf(stderr, "%s", report_text(result).c_str());
        }
        // The histogram script reads the report from a file: --json's, else one beside the PNG.
        if (json_path.empty() && !histogram_path.empty()) {
            json_path = histogram_path + ".json";
        }
        if (!json_path.empty()) {
            std::ofstream out(json_path);
            out << report << '\n';
            if (!out) {
                throw polycut::FileError(json_path, 0, "cannot write the report");
            }
        }
        if (!histogram_path.empty()) {
            const char* script = std::getenv("POLYCUT_BENCH_PLOT");
            plot_histograms(script ? script : POLYCUT_BENCH_PLOT, json_path, histogram_path);
        }
        return 0;
    } catch (const polycut::InputError& e) {
        std::fprintf(
            stderr, "polycut-bench: %s: %s\n%s", e.where().c_str(), e.problem().c_str(), kUsage);
        return 2;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-bench: %s: %s\n", e.where().c_str(), e.problem().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-bench: %s\n", e.what());
        return 1;
    }
}
