#!/usr/bin/env bash
# The main job of `./polycut demo` (called after set-up and the release build).
# Starts polycut-server on the default scene (loopback, ephemeral ports), plays the straight
# incision and the retraction with polycut-scalpel, prints both JSON summaries, and shuts the
# server down (`shutdown`, then SIGTERM/SIGKILL if it does not stop in time).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${POLYCUT_BIN:-build/release}
SERVER="$BIN/server/polycut-server"
SCALPEL="$BIN/clients/polycut-scalpel"
for exe in "$SERVER" "$SCALPEL"; do
  [ -x "$exe" ] || { echo "polycut demo: $exe is missing (build first)" >&2; exit 1; }
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

echo "polycut demo: starting polycut-server on assets/scenes/default.json" >&2
"$SERVER" --scene assets/scenes/default.json --scene-dir assets/scenes \
  --control 'tcp://127.0.0.1:*' --stream 'tcp://127.0.0.1:*' --rate 60 \
  --record-commands "$work/commands.jsonl" >"$work/ready.json" 2>"$work/server.log" &
server_pid=$!

# The server prints one JSON line with the bound endpoints once it is listening.
for _ in $(seq 1 300); do
  [ -s "$work/ready.json" ] && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log" >&2; exit 1; }
  sleep 0.1
done
[ -s "$work/ready.json" ] || { echo "polycut demo: the server did not start" >&2; exit 1; }
control=$(sed -n 's/.*"control":"\([^"]*\)".*/\1/p' "$work/ready.json")
echo "polycut demo: server ready, control $control" >&2

status=0
for script in straight_incision retraction; do
  echo "polycut demo: playing assets/scripts/$script.json" >&2
  "$SCALPEL" --server "$control" "assets/scripts/$script.json" || status=1
done

echo "polycut demo: shutting the server down" >&2
"$SCALPEL" --server "$control" --shutdown >/dev/null || true
for _ in $(seq 1 100); do
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$server_pid" 2>/dev/null; then
  echo "polycut demo: the server did not stop; terminating it" >&2
  kill -TERM "$server_pid" 2>/dev/null || true
fi
wait "$server_pid" 2>/dev/null || true
server_pid=""
echo "polycut demo: server log (last lines):" >&2
tail -n 4 "$work/server.log" >&2
echo "polycut demo: $(grep -c '"request"' "$work/commands.jsonl") commands recorded; replay:" >&2
"$SERVER" --replay "$work/commands.jsonl" --scene-dir assets/scenes >&2 || status=1
exit $status
