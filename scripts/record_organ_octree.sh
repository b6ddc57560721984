#!/usr/bin/env bash
# The octree organ cut live, recorded (issue 15 items 3-4): polycut-server on
# assets/scenes/organ_octree.json (its 79,872-triangle embedded surface, on a table) with a
# command log, polycut-scalpel plays assets/scripts/organ_octree_incision.json, the server is
# shut down, and the session is rendered offline from its log, every other tick, to
# $POLYCUT_OUT/organ_octree_cut.mp4 (default out/): the detailed surface being cut, frame for
# frame, however slowly the live server ran. Called by scripts/demo.sh; runs alone too.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${POLYCUT_BIN:-build/release}
SERVER="$BIN/server/polycut-server"
SCALPEL="$BIN/clients/polycut-scalpel"
RECORD="$BIN/clients/record/polycut-record"
OUT=${POLYCUT_OUT:-out}
for exe in "$SERVER" "$SCALPEL" "$RECORD"; do
  [ -x "$exe" ] || { echo "record_organ_octree: $exe is missing (build first)" >&2; exit 1; }
done
work=$(mktemp -d)
server_pid=""
cleanup() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then
    kill -TERM "$server_pid" 2>/dev/null || true
    sleep 1
    kill -KILL "$server_pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT

"$SERVER" --scene assets/scenes/organ_octree.json --scene-dir assets/scenes \
  --control 'tcp://127.0.0.1:*' --stream 'tcp://127.0.0.1:*' --rate 60 \
  --record-commands "$work/commands.jsonl" >"$work/ready.json" 2>"$work/server.log" &
server_pid=$!
for _ in $(seq 1 600); do
  [ -s "$work/ready.json" ] && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log" >&2; exit 1; }
  sleep 0.1
done
[ -s "$work/ready.json" ] || { echo "record_organ_octree: the server did not start" >&2; exit 1; }
control=$(sed -n 's/.*"control":"\([^"]*\)".*/\1/p' "$work/ready.json")
echo "record_organ_octree: playing assets/scripts/organ_octree_incision.json" >&2
"$SCALPEL" --server "$control" assets/scripts/organ_octree_incision.json >"$work/scalpel.json"
echo "record_organ_octree: scalpel: $(cat "$work/scalpel.json")" >&2
"$SCALPEL" --server "$control" --shutdown >/dev/null || true
for _ in $(seq 1 100); do
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
wait "$server_pid" 2>/dev/null || true
server_pid=""
mkdir -p "$OUT"
cp "$work/commands.jsonl" "$OUT/organ_octree_commands.jsonl"
echo "record_organ_octree: rendering the session offline to $OUT/organ_octree_cut.mp4" >&2
"$RECORD" --offline assets/scenes/organ_octree.json --commands "$OUT/organ_octree_commands.jsonl" \
  --scene-dir assets/scenes --every 2 --mp4 "$OUT/organ_octree_cut.mp4" \
  --stills "$OUT/organ_octree_stills" --still-every 30
