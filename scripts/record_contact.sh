#!/usr/bin/env bash
# The contact scenes recorded off screen (issue 15 item 4), with their tools drawn:
#   out/organ_table_probe.mp4  the organ settles on the table, a 1 cm probe presses its top
#   out/incision_spatula.mp4   a spatula (thin blade box) comes down into an incision and
#                              presses one lip aside
# Both scenes script their tool along keyframes (scene key `tools`), so no client is needed:
# polycut-record replays the scene for its own motion (--frames, every other tick) and draws
# each tool where it was during the tick. $POLYCUT_OUT (default out/) receives the videos and
# a few stills. Called by scripts/demo.sh; runs alone too.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${POLYCUT_BIN:-build/release}
RECORD="$BIN/clients/record/polycut-record"
OUT=${POLYCUT_OUT:-out}
[ -x "$RECORD" ] || { echo "record_contact: $RECORD is missing (build first)" >&2; exit 1; }
mkdir -p "$OUT"
record() { # scene, ticks
  local name=$1 ticks=$2
  echo "record_contact: rendering assets/scenes/$name.json ($ticks ticks) to $OUT/$name.mp4" >&2
  "$RECORD" --offline "assets/scenes/$name.json" --scene-dir assets/scenes \
    --frames $((ticks / 2)) --every 2 --size 480x360 --mp4 "$OUT/$name.mp4" \
    --stills "$OUT/${name}_stills" --still-every 30
}
record organ_table_probe 210
record incision_spatula 240
