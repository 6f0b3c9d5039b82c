#!/usr/bin/env bash
# polyloc simulate, as a user types it: 10 s of the lab tour as MCAP with --json (keys, real-time
# factor > 1), the TUM ground truth and the PNG; the same seed gives the same bytes; a broken
# scenario gives an error naming file, line and key.
set -euo pipefail
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
[ "$(head -c 8 "$tmp/run.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]
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
echo OK
