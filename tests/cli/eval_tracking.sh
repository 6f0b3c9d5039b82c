#!/bin/bash
# polyloc eval tracking: a short run of the crowd scenario; the JSON has the documented fields and
# sane values, the plot is written, --tracking replaces the config's section, errors name the
# option or the key.
set -euo pipefail
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
test -s "$tmp/t.png"
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
