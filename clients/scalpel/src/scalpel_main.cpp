// polycut-scalpel: plays a scalpel script against a polycut-server and prints a JSON summary.
//   polycut-scalpel [--server tcp://127.0.0.1:5555] [--shutdown] [--no-stream] [SCRIPT.json]
// With --shutdown the server is asked to stop after the script (or right away without one).
// Exit status: 0 when every request succeeded, 1 when some got errors or no reply, 2 for bad
// usage, an unreadable script or an unreachable server.
#include "player.hpp"
#include "script.hpp"

#include <cstdio>
#include <iostream>
#include <string>

namespace {

int usage(const std::string& why) {
    std::fprintf(stderr,
        "polycut-scalpel: %s\n"
        "usage: polycut-scalpel [--server EP] [--shutdown] [--no-stream] [SCRIPT.json]\n",
        why.c_str());
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    polycut::scalpel::PlayOptions options;
    std::string script_path;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--server" && i + 1 < argc) {
            options.server = argv[++i];
        } else if (a == "--shutdown") {
            options.shutdown_after = true;
        } else if (a == "--no-stream") {
            options.subscribe = false;
        } else if (a == "--help" || a == "-h") {
            usage("help");
            return 0;
        } else if (!a.empty() && a[0] == '-') {
            return usage("unknown option " + a);
        } else if (script_path.empty()) {
            script_path = a;
        } else {
            return usage("only one script");
        }
    }
    try {
        if (script_path.empty()) {
            if (!options.shutdown_after) {
                return usage("no script given");
            }
            const bool ok = polycut::scalpel::send_shutdown(options);
            std::cout << (ok ? R"({"shutdown":true})" : R"({"shutdown":false})") << std::endl;
            return ok ? 0 : 1;
        }
        const auto script = polycut::scalpel::load_script(script_path);
        int errors = 0;
        std::cout << polycut::scalpel::play(script, options, errors) << std::endl;
        return errors == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-scalpel: %s\n", e.what());
        return 2;
    }
}
