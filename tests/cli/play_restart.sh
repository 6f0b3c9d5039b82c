#!/bin/bash
# `polyloc play --drive` follows a polylocd that dies and is started again: while it is gone play
# says so (not "restarted"), and once the new one is up, the simulated base's VRS and cmd_vel
# readers move to the new segment with the feed, so that commands flow again (they stayed on the
# dead segment and the loop stalled while play printed "re-attached").
# Usage: bash play_restart.sh <path-to-polyloc> <source-dir>
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
BIN=$(dirname "$POLYLOC")
PY=/usr/bin/python3
cd "$SRC"
tmp=$(mktemp -d)
instance=restart_$$
pids=()
daemon=
trap 'for p in "${pids[@]}" $daemon; do kill -9 $p 2>/dev/null || true; done; rm -rf "$tmp" /dev/shm/polyloc.$instance' EXIT

sed -e "s|^map: ../lab.obj|map: $SRC/maps/lab.obj|" -e "s|^rig: ../rigs/lisa.yaml|rig: $SRC/maps/rigs/lisa.yaml|" \
    -e "s|  instance: lab .*|  instance: $instance\n  clock: source\n  live: {port: 0}|" -e "s|  control: {port: 7410}.*|  control: {enabled: false}|" \
    maps/config/lab.yaml > "$tmp/daemon.yaml"
"$POLYLOC" map navgrid --config maps/config/lab.yaml --out "$tmp/nav.yaml" --no-preview > /dev/null
start_daemon() {
  "$BIN/polylocd" --config "$tmp/daemon.yaml" --init 2.0,1.75,0 --threads 2 --log-level warn 2>> "$tmp/polylocd.log" &
  daemon=$!
}
start_daemon
"$BIN/polynav" --shm "$instance" --grid "$tmp/nav.yaml" --zones maps/nav/lab.yaml --goals "corridor hose cabinet" \
  --quiet > /dev/null 2> "$tmp/polynav.log" &
pids+=($!)
"$POLYLOC" play --scenario maps/scenarios/lab_nav.yaml --shm "$instance" --drive --rate 1 --duration 30 --json --quiet \
  > "$tmp/drive.json" 2> "$tmp/play.err" &
play=$!
pids+=($play)

sleep 8
kill -9 "$daemon"
wait "$daemon" 2>/dev/null || true
sleep 3   # gone for a while: play must say so, and not that it re-attached
grep -q "stopped or died" "$tmp/play.err" || { cat "$tmp/play.err" >&2; echo "FAIL: play did not notice polylocd died" >&2; exit 1; }
if grep -q "re-attached\|is back (" "$tmp/play.err"; then cat "$tmp/play.err" >&2; echo "FAIL: play claims a re-attachment while polylocd is dead" >&2; exit 1; fi
start_daemon
wait "$play" || { cat "$tmp/play.err" >&2; echo "FAIL: play --drive failed" >&2; exit 1; }
cat "$tmp/play.err"
"$PY" - "$tmp/drive.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
loop = j["loop"]
print(loop)
assert loop["reattached"] == 1, loop
# 30 s at 1x with the daemon gone ~4 s and back after its start: the controller answered again.
assert loop["commands_since_attach"] >= 20, loop
assert j["base"]["rejected"] == 0, j["base"]
PYEOF
grep -q "is back (generation" "$tmp/play.err" || { echo "FAIL: play did not say polylocd is back" >&2; exit 1; }
echo "play_restart: ok"
