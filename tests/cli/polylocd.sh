#!/bin/bash
# polylocd end to end, as a user runs it: the config is checked (a bad key is named with its
# line), the daemon starts, `polyloc play` feeds 12 s of the lab tour simulated live at real
# time, the poses that come back follow the ground truth, no frame is dropped, SIGTERM
# stops the daemon cleanly; play without a daemon says which segment is missing.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
POLYLOCD=$(dirname "$POLYLOC")/polylocd
PY=$(command -v python3)
cd "$SRC"
tmp=$(mktemp -d)
instance=clitest_$$
pid=
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp" /dev/shm/polyloc.$instance' EXIT

"$POLYLOCD" --config maps/config/lab.yaml --check | grep -q "ok (rig 'lisa', 7 sensors, instance 'lab')"
cat > "$tmp/bad.yaml" <<YAML
map: $SRC/maps/lab.obj
robot: {footprint: [[0.3, 0.25], [-0.3, 0.25], [-0.3, -0.25], [0.3, -0.25]], height: 1.2}
rig: lisa
polylocd:
  instance: x
  slotz: 4
YAML
if "$POLYLOCD" --config "$tmp/bad.yaml" --check 2> "$tmp/err"; then echo "bad config accepted" >&2; exit 1; fi
grep -q "bad.yaml:6" "$tmp/err" && grep -q "slotz" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
# --check checks what a start checks: a control address that is no IPv4 address, with file:line.
sed -e 's|^  slotz: 4|  control: {bind: "999.1.1.1"}|' "$tmp/bad.yaml" > "$tmp/bind.yaml"
if "$POLYLOCD" --config "$tmp/bind.yaml" --check 2> "$tmp/err"; then echo "bad control.bind accepted by --check" >&2; exit 1; fi
grep -q "bind.yaml:6" "$tmp/err" && grep -q "999.1.1.1' is not an IPv4 address" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
# A port beyond 65535 is refused (a narrowing cast made 70000 port 4464), as usage: exit 2.
rc=0; "$POLYLOCD" --config maps/config/lab.yaml --control-port 70000 --check 2> "$tmp/err" || rc=$?
[ $rc -eq 2 ] && grep -q "control-port" "$tmp/err" || { echo "--control-port 70000: exit $rc" >&2; cat "$tmp/err" >&2; exit 1; }

if "$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --wait 0.3 --duration 1 2> "$tmp/err"; then
  echo "play without polylocd succeeded" >&2; exit 1
fi
grep -q "/polyloc.$instance" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }

"$POLYLOCD" --config maps/config/lab.yaml --instance "$instance" --control-port 0 --init 1.3,1.75,0 --threads 2 \
  2> "$tmp/polylocd.log" &
pid=$!
"$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --duration 12 --json --quiet \
  --plot "$tmp/play.png" > "$tmp/play.json"
"$PY" - "$tmp/play.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
for k in ("sent", "poses", "latency_ms", "dropped", "rejected", "per_channel", "polylocd", "accuracy"):
    assert k in j, k
assert j["poses"] > 30, j["poses"]
lost = j["dropped"] + j["rejected"]
# No frame lost while polylocd keeps up: it loses one only as stale, read 500 ms after its stamp,
# or as an overrun, when its ring (0.8 s and more) laps it. docs/benchmarks.md: latency p99 20 ms
# on a quiet machine, 0 of 18,908 frames lost over the whole tour, also with 3 builds loading it.
# Only when polylocd visibly fell behind, a pose published 250 ms (half of max_age) or more after
# its scan, may frames be lost, at most 1 s of them. Measured at load 6-8 on these 2 cores (other
# builds running): latency p99 300-640 ms, and 0 lost in 6 of 9 runs, else 13, 77, 82 and 87 of
# 1,628 (0.1-0.6 s of frames, all stale or ToF overruns, at about 4 s into the run). The 2 %
# allowed before failed two of those runs and would pass a quiet-machine polylocd that drops
# 0.2 s of frames.
import os
# make sanitize runs this 5-15x slower than real time needs: frames lost and the error that
# follows measure the sanitizer there; what it checks is that polylocd runs and stops clean.
sanitized = os.environ.get("POLYLOC_SANITIZE") == "1"
kept_up = j["latency_ms"]["max"] < 250
print(f"latency max {j['latency_ms']['max']:.0f} ms, play late {j['late']}, lost {lost} of {j['sent']}")
other = {ch: {k: e[k] for k in ("nan", "size", "future") if e[k]} for ch, e in j["polylocd"]["inputs"].items()}
assert not any(other.values()), ("frames rejected as broken", other)
if sanitized:
    print("sanitizer build: frame loss and accuracy not checked")
elif kept_up:
    assert lost == 0, ("lost", lost, "of", j["sent"], "though polylocd kept up", j["polylocd"]["inputs"])
else:
    assert lost <= j["sent"] / j["wall_s"], ("lost", lost, "of", j["sent"], "more than 1 s of frames", j["polylocd"]["inputs"])
# docs/benchmarks.md, polylocd end to end on the lab tour: ATE 3.5 mm, p95 6.7 mm; 1.5x of each
# (these 12 s: 3.1 mm and 6.3 mm).
assert sanitized or (j["accuracy"]["ate_rmse_m"] <= 1.5 * 0.0035 and j["accuracy"]["p95_pos_err_m"] <= 1.5 * 0.0067), j["accuracy"]
assert j["latency_ms"]["p50"] > 0
for ch in ("odom", "scan/s300_front_left", "depth/tof_front"):
    assert j["per_channel"][ch] > 0 and j["polylocd"]["inputs"][ch]["taken"] > 0, ch
assert j["polylocd"]["vrs"] > 50 and j["polylocd"]["tracks"] > 50, j["polylocd"]
print("polylocd ok:", j["poses"], "poses, p95", round(j["accuracy"]["p95_pos_err_m"], 4), "m, latency p50",
      round(j["latency_ms"]["p50"], 2), "ms, lost", lost)
PYEOF
# The plot (viz/localize_plot.cpp): truth blue, the poses polylocd published red (the lab map
# has 253 red pixels of its own, no blue): 292 blue, 454 red here; required half the truth's,
# the map's red plus half the estimate's.
"$PY" tests/tools/png_check.py "$tmp/play.png" --min-size 1000x600 --min-colours 300 --ink 0.05,0.3 \
  --colour truth=285ADC:40:146 --colour estimate=DC1E1E:40:353

# The control endpoint of the running daemon (its port from the log: --control-port 0).
port=$(sed -n 's/.*control endpoint on 127.0.0.1:\([0-9]*\).*/\1/p' "$tmp/polylocd.log" | head -1)
[ -n "$port" ] || { cat "$tmp/polylocd.log" >&2; exit 1; }
"$POLYLOC" ctl --port "$port" ping > /dev/null
"$POLYLOC" ctl --port "$port" getpose --json > "$tmp/pose.json"
"$POLYLOC" ctl --port "$port" scanners --json > "$tmp/scanners.json"
"$POLYLOC" ctl --port "$port" scan 1 --json > "$tmp/scan.json"
"$POLYLOC" ctl --port "$port" setca 0 > /dev/null
"$POLYLOC" ctl --port "$port" getca --json > "$tmp/ca.json"
"$POLYLOC" ctl --port "$port" status --json > "$tmp/status.json"
"$PY" - "$tmp" <<'PYEOF'
import json, sys, os
d = sys.argv[1]
load = lambda n: json.load(open(os.path.join(d, n)))
play, pose, sc, scan, ca, st = (load(n) for n in ("play.json", "pose.json", "scanners.json", "scan.json", "ca.json", "status.json"))
# The answers, not only that there are some: the pose polylocd tracks, the lisa rig's six planar
# scanners behind the VRS, a scan of the first one's beam count, the switch just set, the status.
assert pose["pose_status"] == "tracking" and pose["particles"] > 0, pose
names = [s["name"] for s in sc["scanners"]]
assert names[0] == "vrs" and len(names) == 7, names
assert scan["beams"] == sc["scanners"][1]["beams"] > 0, (scan["beams"], sc["scanners"][1])
assert ca["collision_avoidance"] is False, ca
assert st["pose_status"] == "tracking" and st["unfit"] is False and len(st["inputs"]) == 8, st
assert all(i["taken"] > 0 for i in st["inputs"]), st["inputs"]
print("ctl getpose:", json.dumps(pose)[:200])
print("ctl scanners:", json.dumps(sc)[:200])
print("ctl status:", json.dumps(st)[:300])
PYEOF
kill -TERM $pid
wait $pid
pid=
grep -q "stopped after" "$tmp/polylocd.log" || { cat "$tmp/polylocd.log" >&2; exit 1; }
