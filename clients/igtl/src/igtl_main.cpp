// polycut-igtl: 3D Slicer (OpenIGTLinkIF) in front of polycut-server (docs/slicer.md).
//   polycut-igtl [--server EP] [--host 127.0.0.1] [--port 18944] [--device NAME] [--rate HZ]
//                [--units mm|m] [--blade-length M] [--grab-stiffness N_PER_M] [--idle S]
//                [--allow-remote] [--quiet]
// Prints one JSON line on stdout once listening: {"port": PORT}.
#include "igtl_bridge.hpp"
#include "polycut/common/error.hpp"

#include <arpa/inet.h>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>

namespace {

std::atomic<bool> g_stop { false };
extern "C" void on_signal(int) {
    g_stop.store(true);
}

const char* kUsage
    = "usage: polycut-igtl [--server EP] [--host ADDR] [--port N] [--device NAME] [--rate HZ]\n"
      "                    [--units mm|m] [--blade-length M] [--grab-stiffness N_PER_M]\n"
      "                    [--idle S] [--allow-remote] [--quiet]\n"
      "An OpenIGTLink server for 3D Slicer: sends the surface as POLYDATA (cell scalar cut_tag:\n"
      "1 skin, 2 cut) and reads TRANSFORMs: a device named *scalpel* or *blade* cuts (blade from\n"
      "the origin along local z), any other device grabs and pulls (docs/slicer.md).\n"
      "defaults: --server tcp://127.0.0.1:5555 --host 127.0.0.1 --port 18944 --device polycut\n"
      "          --rate 30 --units mm --blade-length 0.03 --grab-stiffness 400 --idle 0.3\n";

double number(const std::string& option, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
        throw polycut::InputError(option,
            "needs a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '"
                + text + "'");
    }
    return v;
}

void print_port(int port) {
    std::cout << "{\"port\": " << port << "}" << std::endl;
}

} // namespace

int main(int argc, char** argv) {
    using polycut::InputError;
    try {
        polycut::igtl_bridge::BridgeOptions options;
        bool allow_remote = false;
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--help" || a == "-h") {
                std::cout << kUsage;
                return 0;
            }
            if (a == "--quiet" || a == "--allow-remote") {
                (a == "--quiet" ? options.quiet : allow_remote) = true;
                continue;
            }
            if (i + 1 >= argc) {
                throw InputError(a, "unknown option or missing value");
            }
            const std::string v = argv[++i];
            if (a == "--server") {
                options.control = v;
            } else if (a == "--host") {
                options.host = v;
            } else if (a == "--port") {
                options.port = int(number(a, v, 0, 65535));
            } else if (a == "--device") {
                if (v.empty() || v.size() > 20) {
                    throw InputError(a, "an OpenIGTLink device name has 1 to 20 characters");
                }
                options.device = v;
            } else if (a == "--rate") {
                options.rate_hz = number(a, v, 0.1, 1000);
            } else if (a == "--units") {
                if (v != "mm" && v != "m") {
                    throw InputError(a, "mm (3D Slicer) or m");
                }
                options.mm_per_m = v == "mm" ? 1000.0 : 1.0;
            } else if (a == "--blade-length") {
                options.blade_length = number(a, v, 1e-4, 1);
            } else if (a == "--grab-stiffness") {
                options.grab_stiffness = number(a, v, 1e-3, 1e9);
            } else if (a == "--idle") {
                options.idle_s = number(a, v, 0.01, 60);
            } else {
                throw InputError(a, "unknown option");
            }
        }
        in_addr address {};
        const bool loopback = options.host == "localhost"
            || (::inet_pton(AF_INET, options.host.c_str(), &address) == 1
                && (ntohl(address.s_addr) >> 24) == 127);
        if (!loopback && !allow_remote) {
            throw InputError("--host",
                options.host
                    + " is not a loopback address; anyone who reaches it can cut: add "
                      "--allow-remote to mean it");
        }
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        const auto summary = polycut::igtl_bridge::run_bridge(options, g_stop, print_port);
        if (!options.quiet) {
            std::fprintf(stderr,
                "polycut-igtl: %ld clients, %ld POLYDATA sent, %ld TRANSFORMs, %ld snapshots\n",
                summary.clients, summary.polydata_sent, summary.transforms, summary.snapshots);
        }
        return 0;
    } catch (const polycut::InputError& e) {
        std::fprintf(
            stderr, "polycut-igtl: %s: %s\n%s", e.where().c_str(), e.problem().c_str(), kUsage);
        return 2;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-igtl: %s: %s\n", e.where().c_str(), e.problem().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-igtl: %s\n", e.what());
        return 1;
    }
}
