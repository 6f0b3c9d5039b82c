#!/usr/bin/env bash
# polyloc info, as a user types it: a small CARMEN log written here (text and --json report),
# and the error path for a missing file.
# Usage: bash info.sh <path-to-polyloc> <source-dir>
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

# A missing file: non-zero exit, and the message names the file.
status=0
"$polyloc" info "$tmp/no_such_log.clf" >"$tmp/out" 2>"$tmp/err" || status=$?
[[ $status -eq 1 ]] || fail "missing file: exit status $status, expected 1"
grep -q "no_such_log.clf" "$tmp/err" || fail "missing file: message does not name it: $(cat "$tmp/err")"
grep -q "does not exist" "$tmp/err" || fail "missing file: message does not say why: $(cat "$tmp/err")"

# Odometry at 10 Hz for 2 s (21 messages), a front laser at 5 Hz (11, each with its laser pose),
# one unknown type twice, one malformed line.
{
  echo "# written by info.sh"
  echo "PARAM robot_front_laser_max 50.0 100.0 host 0.0"
  for i in $(seq 0 20); do
    t="$((100 + i / 10)).$((i % 10))"
    echo "ODOM 1.0 2.0 0.1 0.5 0.0 0.0 $t host $i"
    if (( i % 2 == 0 )); then echo "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 $t host $i"; fi
  done
  echo "TRUEPOS 1 2 3 1 2 3 101.0 host 1"
  echo "TRUEPOS 1 2 3 1 2 3 101.1 host 1"
  echo "FLASER 180 1.0 2.0 0 0 0 0 0 0 101.5 host 1"
} >"$tmp/run.clf"

"$polyloc" info "$tmp/run.clf" >"$tmp/out"
grep -q "^format: *carmen$" "$tmp/out" || fail "text report: $(cat "$tmp/out")"
grep -q "^duration: *2.000 s$" "$tmp/out" || fail "text report duration: $(cat "$tmp/out")"
grep -Eq "^/odom +nav_msgs/msg/Odometry +21 +10.00$" "$tmp/out" || fail "text report topics: $(cat "$tmp/out")"

"$polyloc" info "$tmp/run.clf" --json >"$tmp/json"
python3 - "$tmp/json" "$tmp/run.clf" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["format"] == "carmen" and r["path"] == sys.argv[2], r
assert abs(r["duration_s"] - 2.0) < 1e-9, r["duration_s"]
assert r["start_ns"] == 100_000_000_000 and r["end_ns"] == 102_000_000_000, r
assert r["messages"] == 43, r
t = r["topics"]
assert set(t) == {"/odom", "/front_laser", "/front_laser_pose"}, t
assert t["/front_laser_pose"]["type"] == "geometry_msgs/msg/PoseStamped" and t["/front_laser_pose"]["count"] == 11, t
assert t["/odom"] == {"type": "nav_msgs/msg/Odometry", "count": 21, "rate_hz": 10.0}, t["/odom"]
assert t["/front_laser"]["type"] == "sensor_msgs/msg/LaserScan" and t["/front_laser"]["count"] == 11, t
assert abs(t["/front_laser"]["rate_hz"] - 5.0) < 1e-9, t
assert r["rejected"] == 2, r
assert any("TRUEPOS" in w for w in r["warnings"]), r["warnings"]
assert any("run.clf:" in w and "FLASER: expected 180 ranges, got 2" in w for w in r["warnings"]), r["warnings"]
PY
echo "info: ok"
