#!/bin/bash
# polyloc perceive: 30 s of the lab tour simulated, then perceived; the JSON has the documented
# metrics (depth, tracking, VRS against the simulator's ground-truth topics) within bounds, the
# output MCAP holds /vrs, /vrs/localization and /tracks, snapshots are written; bad arguments name
# what is wrong.
set -euo pipefail
POLYLOC=$1
SRC=$2
PY=$(command -v python3)
cd "$SRC"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$POLYLOC" simulate --scenario maps/scenarios/lab_tour.yaml --duration 30 --out "$tmp/run.mcap" > /dev/null
out=$("$POLYLOC" perceive --input "$tmp/run.mcap" --config maps/config/lab.yaml --out "$tmp/p" --snapshots 2 --json)
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
for k in ("depth_outlier_removed", "depth_valid_kept", "mota", "track_rmse_m", "id_switches_per_100s",
          "vrs_rmse_m", "vrs_update_ms_p99", "vrs_updates", "frames", "snapshots", "counters"):
    assert k in j, k
assert j["frames_without_pose"] == 0 and j["vrs_updates"] > 300, j
assert j["depth_outlier_removed"] >= 0.9 and j["depth_valid_kept"] >= 0.9, j
assert j["vrs_rmse_m"] is not None and j["vrs_rmse_m"] < 0.2 and j["vrs_scored_segments"] > 1000, j
assert j["mota"] is not None and -1 <= j["mota"] <= 1, j
assert len(j["snapshots"]) == 2, j
print("perceive ok: depth", round(j["depth_outlier_removed"], 3), round(j["depth_valid_kept"], 3), "VRS RMSE", round(j["vrs_rmse_m"], 3))
'
test -s "$tmp/p/vrs_0.png"
"$POLYLOC" info "$tmp/p/perception.mcap" --json | "$PY" -c '
import json, sys
t = json.load(sys.stdin)["topics"]
assert t["/vrs"]["type"] == "sensor_msgs/msg/LaserScan" and t["/vrs"]["count"] > 300, t
assert t["/vrs/localization"]["count"] == t["/vrs"]["count"], t
assert t["/tracks"]["type"] == "polyloc_msgs/msg/TrackArray", t
'
if "$POLYLOC" perceive --input "$tmp/run.mcap" --config maps/config/lab.yaml --out "$tmp/q" --pose sideways 2> "$tmp/err"; then
  echo "bad --pose accepted"; exit 1
fi
grep -q -- "--pose" "$tmp/err"
if "$POLYLOC" perceive --input "$tmp/missing.mcap" --config maps/config/lab.yaml --out "$tmp/q" 2> "$tmp/err"; then
  echo "missing input accepted"; exit 1
fi
grep -q "missing.mcap" "$tmp/err"
echo "perceive cli ok"
