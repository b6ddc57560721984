// polycut-web: the browser viewer's server (docs/viewer.md). Serves the bundled three.js app and
// bridges each browser's WebSocket to polycut-server's ZeroMQ protocol, adding nothing to it.
//   polycut-web [--server tcp://127.0.0.1:5555] [--http 127.0.0.1:8080] [--app DIR]
//               [--scene-dir DIR] [--allow-remote] [--quiet]
// Prints one JSON line on stdout once listening: {"url": "http://HOST:PORT/", "port": PORT}.
#include "polycut/common/error.hpp"
#include "web_server.hpp"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

namespace {

const char* kUsage
    = "usage: polycut-web [--server EP] [--http HOST:PORT] [--app DIR] [--scene-dir DIR]\n"
      "                   [--allow-remote] [--quiet]\n"
      "Serves the browser viewer and bridges its WebSocket to polycut-server (docs/viewer.md).\n"
      "defaults: --server tcp://127.0.0.1:5555 --http 127.0.0.1:8080 (port 0 = any free port)\n"
      "          --app " POLYCUT_WEB_APP_DIR "\n"
      "          --scene-dir " POLYCUT_WEB_SCENE_DIR "\n"
      "A non-loopback --http address needs --allow-remote (the viewer can cut and load scenes).\n";

polycut::web::WebOptions parse(int argc, char** argv, bool& quiet) {
    polycut::web::WebOptions options;
    options.app_dir = POLYCUT_WEB_APP_DIR;
    options.scene_dir = POLYCUT_WEB_SCENE_DIR;
    bool allow_remote = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::cout << kUsage;
            std::exit(0);
        }
        if (a == "--quiet") {
            quiet = true;
            continue;
        }
        if (a == "--allow-remote") {
            allow_remote = true;
            continue;
        }
        if (i + 1 >= argc) {
            throw polycut::InputError(a, "unknown option or missing value");
        }
        const std::string v = argv[++i];
        if (a == "--server") {
            options.control = v;
        } else if (a == "--app") {
            options.app_dir = v;
        } else if (a == "--scene-dir") {
            options.scene_dir = v;
        } else if (a == "--http") {
            const auto colon = v.rfind(':');
            if (colon == std::string::npos || colon + 1 == v.size()) {
                throw polycut::InputError(a, "needs HOST:PORT, e.g. 127.0.0.1:8080");
            }
            options.host = v.substr(0, colon);
            if (options.host.size() > 2 && options.host.front() == '[') {
                options.host = options.host.substr(1, options.host.size() - 2);
            }
            char* end = nullptr;
            const long port = std::strtol(v.c_str() + colon + 1, &end, 10);
            if (*end != '\0' || port < 0 || port > 65535) {
                throw polycut::InputError(a, "port must be an integer in [0, 65535]");
            }
            options.port = static_cast<std::uint16_t>(port);
        } else {
            throw polycut::InputError(a, "unknown option");
        }
    }
    if (!polycut::web::is_loopback(options.host) && !allow_remote) {
        throw polycut::InputError("--http",
            options.host
                + " is not a loopback address; anyone who reaches it can cut and load "
                  "scenes: add --allow-remote to mean it");
    }
    return options;
}

} // namespace

int main(int argc, char** argv) {
    try {
        bool quiet = false;
        const polycut::web::WebOptions options = parse(argc, argv, quiet);
        polycut::web::WebServer server(options);
        const std::string host
            = options.host.find(':') != std::string::npos ? "[" + options.host + "]" : options.host;
        const std::string url = "http://" + host + ":" + std::to_string(server.port()) + "/";
        std::cout << nlohmann::json { { "url", url }, { "port", server.port() } }.dump()
                  << std::endl;
        if (!quiet) {
            std::fprintf(stderr, "polycut-web: open %s (server %s; Ctrl-C to stop)\n", url.c_str(),
                options.control.c_str());
        }
        server.run(); // until SIGINT or SIGTERM
        return 0;
    } catch (const polycut::InputError& e) {
        std::fprintf(
            stderr, "polycut-web: %s: %s\n%s", e.where().c_str(), e.problem().c_str(), kUsage);
        return 2;
    } catch (const polycut::Error& e) {
        std::fprintf(stderr, "polycut-web: %s: %s\n", e.where().c_str(), e.problem().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "polycut-web: %s\n", e.what());
        return 1;
    }
}
