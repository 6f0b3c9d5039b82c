#!/bin/bash
# polyloc eval tracking: a short run of the crowd scenario; the JSON has the documented fields and
# sane values, the plot is written, --tracking replaces the config's section, errors name the
# option or the key.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
PY=$(command -v python3)
cd "$SRC"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$POLYLOC" eval tracking --scenario maps/scenarios/crowd.yaml --duration 10 --json --plot "$tmp/t.png")
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
for k in ("mota", "motp_m", "track_rmse_m", "id_switches", "id_switches_per_100s", "track_seconds",
          "misses", "false_positives", "ground_truth", "reentries", "strict", "scans", "detections"):
    assert k in j, k
assert j["people"] == 8 and j["sim_duration_s"] == 10 and j["ground_truth"] > 300, j
assert 0.5 < j["mota"] <= 1 and 0 < j["track_rmse_m"] < 0.2, j
assert j["scans"] == 2 * j["frames"] and j["rejected_scans"] == 0, j
print("eval tracking ok: MOTA", round(j["mota"], 3))
'
# The plot (viz/tracking_plot.cpp): robot path blue, people walking in view purple, each track in
# the colour of its id. These 10 s: 220 blue, 5,118 purple, tracks 499 green and 442 magenta
# pixels (a 0.5 s run: 11, 780, 54, 9): half of each is required.
"$PY" tests/tools/png_check.py "$tmp/t.png" --min-size 1000x600 --min-colours 500 --ink 0.05,0.3 \
  --colour robot=285ADC:40:110 --colour people=963CAA:40:2500 --colour track_green=1EA03C:40:250 \
  --colour track_magenta=C828A0:40:220
"$POLYLOC" eval tracking --scenario maps/scenarios/crowd.yaml --duration 3 --odometry \
  --tracking maps/config/tracking_odometry.yaml --json > /dev/null
printf 'tracking:\n  motion: {margn: 0.1}\n' > "$tmp/bad.yaml"
if "$POLYLOC" eval tracking --scenario maps/scenarios/crowd.yaml --tracking "$tmp/bad.yaml" 2> "$tmp/err"; then
  echo "unknown key accepted"; exit 1
fi
grep -q "margn" "$tmp/err"
if "$POLYLOC" eval tracking --scenario /nonexistent.yaml 2> "$tmp/err"; then echo "missing scenario accepted"; exit 1; fi
grep -q "nonexistent" "$tmp/err"
echo "eval tracking: ok"
