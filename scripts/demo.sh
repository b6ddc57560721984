#!/usr/bin/env bash
# The main job of `./polycut demo` (called after set-up and the release build).
# Runs the headless runner on the default scene and prints its summary.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=build/release
echo "polycut demo: headless run of assets/scenes/default.json" >&2
"$BIN/server/polycut-run" assets/scenes/default.json --steps 60
