#!/usr/bin/env bash
# polyloc simulate, as a user types it: 10 s of the lab tour as MCAP with --json (keys, real-time
# factor > 1), the TUM ground truth and the PNG; the same seed gives the same bytes; a broken
# scenario gives an error naming file, line and key; --duration 0 is all of the scenario.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
run() {
  "$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 10 "$@"
}
if ! out=$(run --out "$tmp/run.mcap" --json --ground-truth "$tmp/gt.tum" --plot "$tmp/run.png" 2>"$tmp/err"); then
  cat "$tmp/err" >&2
  exit 1
fi
echo "$out"
python3 - "$out" "$tmp/run.mcap" <<'PY'
import json, os, sys
j = json.loads(sys.argv[1])
for key in ("realtime_factor", "sim_duration_s", "wall_s", "output_bytes", "messages", "topics"):
    assert key in j, key
assert j["realtime_factor"] > 1, j["realtime_factor"]
assert abs(j["sim_duration_s"] - 10) < 1e-9
assert j["output_bytes"] == os.path.getsize(sys.argv[2])
assert j["topics"]["/odom"] == 501 and j["topics"]["/scan/s300_front_left"] == 126, j["topics"]
assert j["messages"] == sum(j["topics"].values())
PY
# Ground truth at 50 Hz (a header line, then 501 poses); a PNG.
[ "$(grep -vc '^#' "$tmp/gt.tum")" = 501 ]
# The plot (viz/sim_plot.cpp): truth path blue, each sensor's points at the end in its palette
# colour (rig order: s300_front_left red, s300_rear_right green, urg_front orange, urg_left cyan,
# urg_rear magenta, urg_right brown, tof_front teal). Measured: 399 blue, 1,765 green, 1,379
# cyan, 1,511 magenta, 7,496 teal pixels (the lab map draws none of these); half of each required.
python3 tests/tools/png_check.py "$tmp/run.png" --min-size 1000x700 --min-colours 500 --ink 0.05,0.3 \
  --colour truth=285ADC:40:200 --colour s300_rear_right=1EA03C:40:880 --colour urg_left=00AAC8:40:690 \
  --colour urg_rear=C828A0:40:750 --colour tof_front=147878:25:3700
# The recording reads back with the same topics.
"$polyloc" info "$tmp/run.mcap" --json | python3 -c 'import json,sys; t=json.load(sys.stdin)["topics"]; assert len(t) == 16, t'
# Same seed, same bytes; another seed, other bytes. The summary goes to stdout.
run --out "$tmp/again.mcap" >"$tmp/summary.txt"
grep -q '^simulated  10.0 s' "$tmp/summary.txt"
cmp "$tmp/run.mcap" "$tmp/again.mcap"
run --out "$tmp/other.mcap" --seed 2 >/dev/null
! cmp -s "$tmp/run.mcap" "$tmp/other.mcap"
# A scenario with a typo: exit 1, the message names file, line and key.
printf 'config: %s/maps/config/lab.yaml\nroute:\n  waypoints: [[1, 1.75]]\n  max_sped: 1\n' "$src" >"$tmp/bad.yaml"
if "$polyloc" simulate --scenario "$tmp/bad.yaml" --out "$tmp/bad.mcap" 2>"$tmp/err"; then
  echo "a bad scenario was accepted" >&2
  exit 1
fi
grep -q "bad.yaml:4:3: unknown key 'route.max_sped'" "$tmp/err"
# --duration 0 means all of the scenario, as in every command that takes it (a 2 s scenario here).
printf 'base: %s/maps/scenarios/lab_tour.yaml\nduration: 2\n' "$src" > "$tmp/short.yaml"
"$polyloc" simulate --scenario "$tmp/short.yaml" --duration 0 --out "$tmp/all0.mcap" --json > "$tmp/all0.json"
"$polyloc" simulate --scenario "$tmp/short.yaml" --out "$tmp/all.mcap" --json > "$tmp/all.json"
python3 -c 'import json,sys; a,b=(json.load(open(f)) for f in sys.argv[1:3]); assert a["sim_duration_s"] == b["sim_duration_s"] == 2 and a["topics"] == b["topics"], (a, b)' "$tmp/all0.json" "$tmp/all.json"
cmp "$tmp/all0.mcap" "$tmp/all.mcap"
echo OK
