#!/usr/bin/env bash
# The live view from the CLI (docs/live.md): `polyloc localize --live` serves pose, particles,
# scans and the top view while it runs, paced to the recording, and gives the same trajectory as
# without a viewer; `polyloc play --live` serves polylocd's poses beside the truth; a port in use
# is an error naming it for the CLI, and only a logged error for polylocd, which localises on.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
polylocd=$(dirname "$polyloc")/polylocd
tmp=$(mktemp -d)
pids=()
instance=live_cli_$$
cleanup() {
  for p in "${pids[@]}"; do { kill -9 "$p" && wait "$p"; } 2>/dev/null || true; done
  [ -n "${KEEP:-}" ] && echo "kept $tmp" >&2 || rm -rf "$tmp"; rm -f /dev/shm/polyloc.$instance
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$src"
source tests/cli/npm_deps.sh
npm_deps "$src/tests/js" "the live view's viewer"
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

"$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 6 --out "$tmp/run.mcap" >/dev/null

# localize --live, watched by a viewer that subscribes to everything.
port=$(free_port)
"$polyloc" localize --input "$tmp/run.mcap" --config maps/config/lab.yaml --out "$tmp/live.tum" --json \
  --live "$port" --live-rate 1 --live-linger 1 >"$tmp/live.json" 2>"$tmp/live.err" &
loc=$!; pids+=($loc)
for _ in $(seq 100); do curl -sf -o /dev/null "http://127.0.0.1:$port/" && break; sleep 0.1; done
node tests/js/live_viewer.mjs "ws://127.0.0.1:$port" >"$tmp/viewer.json" &
viewer=$!; pids+=($viewer)
wait $loc || { cat "$tmp/live.err" >&2; fail "localize --live failed"; }
kill -TERM $viewer 2>/dev/null || true; wait $viewer || true
grep -q "live view on http://127.0.0.1:$port/" "$tmp/live.err" || fail "localize did not say where the view is"
"$polyloc" localize --input "$tmp/run.mcap" --config maps/config/lab.yaml --out "$tmp/plain.tum" --json >"$tmp/plain.json" 2>/dev/null
cmp -s "$tmp/live.tum" "$tmp/plain.tum" || fail "localize --live changed the trajectory"
/usr/bin/python3 - "$tmp/viewer.json" "$tmp/live.json" <<'PY'
import json, sys
v = json.load(open(sys.argv[1]))["per_topic"]
j = json.load(open(sys.argv[2]))
print("localize --live: viewer got", v)
# 6 s of the tour: about 50 updates, the S300s at 12.5 Hz, the top view at 10 Hz of data time.
need = {"/map": 1, "/polyloc/map_slice": 1, "/tf_static": 1, "/pose": 20, "/tf": 20, "/particles": 20,
        "/scan/s300_front_left": 50, "/polyloc/topview": 20}
low = {k: (v.get(k, 0), n) for k, n in need.items() if v.get(k, 0) < n}
assert not low, ("too few messages (got, wanted)", low)
assert j["ate_rmse_m"] < 0.05, j["ate_rmse_m"]
PY

# A port in use: the CLI stops and names it.
busy=$(free_port)
/usr/bin/python3 -c "import socket,time; s=socket.socket(); s.bind(('127.0.0.1', $busy)); s.listen(); time.sleep(30)" &
holder=$!; pids+=($holder)
sleep 0.3
if "$polyloc" localize --input "$tmp/run.mcap" --config maps/config/lab.yaml --live "$busy" 2>"$tmp/err" >/dev/null; then
  fail "localize --live on a port in use succeeded"
fi
grep -q "127.0.0.1:$busy" "$tmp/err" || { cat "$tmp/err" >&2; fail "the error does not name 127.0.0.1:$busy"; }

# polylocd with its live port in use: the error is logged, localisation goes on; then play --live.
"$polylocd" --config maps/config/lab.yaml --instance $instance --control-port 0 --live-port "$busy" \
  --init 1.3,1.75,0 --threads 2 2>"$tmp/polylocd.log" &
daemon=$!; pids+=($daemon)
port=$(free_port)
"$polyloc" play --scenario maps/scenarios/lab_tour.yaml --shm $instance --duration 4 --quiet --json --live "$port" \
  >"$tmp/play.json" 2>"$tmp/play.err" &
play=$!; pids+=($play)
for _ in $(seq 100); do curl -sf -o /dev/null "http://127.0.0.1:$port/" && break; sleep 0.1; done
node tests/js/live_viewer.mjs "ws://127.0.0.1:$port" >"$tmp/viewer2.json" &
viewer=$!; pids+=($viewer)
wait $play || { cat "$tmp/play.err" >&2; fail "play --live failed"; }
kill -TERM $viewer 2>/dev/null || true; wait $viewer || true
kill -INT $daemon; wait $daemon || { cat "$tmp/polylocd.log" >&2; fail "polylocd did not stop cleanly"; }
grep -q "cannot listen on 127.0.0.1:$busy" "$tmp/polylocd.log" || { cat "$tmp/polylocd.log" >&2; fail "polylocd did not log the busy port"; }
grep -q "goes on without it" "$tmp/polylocd.log" || fail "polylocd did not say it goes on"
/usr/bin/python3 - "$tmp/viewer2.json" "$tmp/play.json" <<'PY'
import json, sys
v = json.load(open(sys.argv[1]))["per_topic"]
j = json.load(open(sys.argv[2]))
import os
print("play --live: viewer got", v, "; polylocd published", j["poses"], "poses")
# make sanitize: polylocd 5-15x slower may not be up and weighing within play's 4 s of real time.
if os.environ.get("POLYLOC_SANITIZE") != "1":
    assert j["poses"] > 10, j["poses"]
    assert v.get("/pose", 0) >= 10, v
assert v.get("/ground_truth", 0) >= 50 and v.get("/map", 0) == 1, v
assert "/particles" not in v, "play has no particles to show"
PY

# play --live of a recording needs the map to draw on.
if "$polyloc" play --input "$tmp/run.mcap" --shm $instance --wait 0 --live "$port" 2>"$tmp/err"; then
  fail "play --live without a map succeeded"
fi
grep -q -- "--live needs --map" "$tmp/err" || { cat "$tmp/err" >&2; fail "no word of --map"; }
echo "live_cli: ok"
