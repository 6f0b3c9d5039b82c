#!/bin/bash
# The closed loop, as a user runs it: polylocd + polynav (the reference controller, linking only
# libpolyloc_client) + the simulated robot of `polyloc play --drive` / `polyloc eval nav`.
#  - eval nav, two missions on the lab: through the 0.75 m door of lab 1 to the island, then to
#    the wall bench: both reached, 0 collisions, 0 danger-zone entries, the door passed without
#    oscillation, goals within 2 cm / 1 deg of the true pose, a PNG of the run;
#  - the same missions again on one polylocd thread: identical, decision for decision;
#  - play --drive with polylocd and polynav started by hand: the robot moves on the commands,
#    the summary counts them;
#  - errors: --drive without a scenario, polynav with an unknown goal, without polylocd, with a
#    footprint of no area.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
BIN=$(dirname "$POLYLOC")
PY=/usr/bin/python3
cd "$SRC"
tmp=$(mktemp -d)
instance=navtest_$$
pids=()
trap 'for p in "${pids[@]}"; do kill -9 $p 2>/dev/null || true; done; rm -rf "$tmp" /dev/shm/polyloc.$instance' EXIT

cat > "$tmp/two.yaml" <<YAML
base: $SRC/maps/scenarios/lab_nav.yaml
navigation:
  zones: $SRC/maps/nav/lab.yaml
  goals: [lab 1 island, lab 1 bench]
  mission_timeout: 120
YAML
# The user's own live view holds the default port 8765 (or someone else does): the polylocd that
# eval nav starts must not try to take it (it opened a live port of its own and logged the clash).
"$PY" -c '
import socket, time
s = socket.socket()
try:
    s.bind(("127.0.0.1", 8765)); s.listen()
except OSError:
    pass  # held by another process already: as good
time.sleep(900)' &
pids+=($!)
"$POLYLOC" eval nav --scenario "$tmp/two.yaml" --missions 2 --json --quiet --plot "$tmp/run.png" --keep "$tmp/keep" > "$tmp/eval.json"
if grep -i "live view" "$tmp/keep/polylocd.log"; then echo "eval nav's polylocd opened a live port" >&2; exit 1; fi
"$PY" - "$tmp/eval.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
m = j["per_mission"]
print({k: j[k] for k in ("reached", "collisions", "danger_entries", "door_passages", "door_oscillations",
                         "min_clearance_m", "goal_error_max_m", "time_vs_optimal", "sim_s")})
assert j["missions"] == 2 and j["reached"] == 2, [x["status"] for x in m]
assert j["collisions"] == 0 and j["danger_entries"] == 0, j
assert j["door_passages"] >= 1 and j["door_oscillations"] == 0, j
for x in m:
    assert x["goal_error_m"] <= 0.02 and x["goal_yaw_error_deg"] <= 1.0, x
    # Measured: 10 cm of clearance at the closest (the margins measured are 1, 2, 3, 5, 7.5, 10,
    # 15 cm): 5 cm, the next below 1.5x worse, fails.
    assert x["min_clearance_m"] >= 0.075, x
# Docking 25 cm in front of the island and the bench: the door and the approach cost time.
# Measured 3.43x the wavefront-optimal path at full speed (both missions): 1.5x worse fails.
assert j["time_vs_optimal"] <= 1.5 * 3.43, j["time_vs_optimal"]
assert j["drive"]["loop"]["vrs_missed"] == 0 and j["drive"]["loop"]["commands_late"] == 0, j["drive"]["loop"]
# polynav's last word is a stop the base takes (it was stamped 0 and refused: the robot kept its
# last command until the base's watchdog).
assert j["drive"]["loop"]["last_command"] == "polynav stopped", j["drive"]["loop"]
assert j["drive"]["loop"]["commands_rejected"] == 0 and j["drive"]["base"]["rejected"] == 0, j["drive"]
PYEOF
head -c 8 "$tmp/run.png" | od -An -c | grep -q "P   N   G"
# The same run again on one polylocd thread: the same missions, decision for decision (lockstep,
# the scenario's own stamps, every sensor frame on an odometry tick). Asked for one, its polylocd
# opens a live view (on a free port; watching changes nothing).
port=$("$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"$POLYLOC" eval nav --scenario "$tmp/two.yaml" --missions 2 --json --quiet --threads 1 --live-port "$port" > "$tmp/eval1.json" &
eval_pid=$!
pids+=($eval_pid)
"$PY" - "$port" "$eval_pid" <<'PYEOF'
import os, socket, sys, time
port, pid = int(sys.argv[1]), int(sys.argv[2])
while True:  # the live view answers while the missions run
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1).close()
        break
    except OSError:
        try:  # gone, or a zombie (this shell reaps it only after this script)
            alive = open("/proc/%d/stat" % pid).read().rsplit(")", 1)[1].split()[0] != "Z"
        except OSError:
            alive = False
        if not alive:
            sys.exit("eval nav --live-port %d: nothing listened while it ran" % port)
        time.sleep(0.1)
PYEOF
wait $eval_pid
if "$POLYLOC" eval nav --scenario "$tmp/two.yaml" --live-port 70000 2> "$tmp/err.txt"; then exit 1; fi
grep -q -- "--live-port" "$tmp/err.txt"
"$PY" - "$tmp/eval.json" "$tmp/eval1.json" <<'PYEOF'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert a["per_mission"] == b["per_mission"] and a["drive"]["final_pose"] == b["drive"]["final_pose"], (a["drive"], b["drive"])
PYEOF

# By hand: polylocd (source clock for lockstep), the controller, the simulated base.
sed -e "s|^map: ../lab.obj|map: $SRC/maps/lab.obj|" -e "s|^rig: ../rigs/lisa.yaml|rig: $SRC/maps/rigs/lisa.yaml|" \
    -e "s|  instance: lab .*|  instance: $instance\n  clock: source|" maps/config/lab.yaml > "$tmp/daemon.yaml"
"$POLYLOC" map navgrid --config maps/config/lab.yaml --out "$tmp/nav.yaml" --no-preview > /dev/null
"$BIN/polylocd" --config "$tmp/daemon.yaml" --control-port 0 --init 2.0,1.75,0 --threads 2 --log-level warn 2> "$tmp/polylocd.log" &
pids+=($!)
"$BIN/polynav" --shm "$instance" --grid "$tmp/nav.yaml" --zones maps/nav/lab.yaml --goals "corridor hose cabinet" \
  --quiet --json > "$tmp/polynav.json" 2> "$tmp/polynav.log" &
nav_pid=$!
pids+=($nav_pid)
"$POLYLOC" play --scenario maps/scenarios/lab_nav.yaml --shm "$instance" --drive --rate 100 --duration 12 --json --quiet > "$tmp/drive.json"
"$PY" - "$tmp/drive.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
print({k: j[k] for k in ("sim_s", "final_pose", "collisions", "loop")})
assert j["loop"]["commands"] > 50 and j["loop"]["vrs_missed"] == 0, j["loop"]
assert j["base"]["rejected"] == 0 and not j["collisions"], j
# 12 s towards the hose cabinet at x = 10.5: it left the start (2.0, 1.75) eastwards.
assert j["final_pose"][0] > 3.5, j["final_pose"]
PYEOF
# Stopped by a signal mid-mission (as a supervisor stops it), polynav's last word is a stop
# stamped after its last command, which a base takes (one stamped 0 was refused).
pydir=$BIN/../python
if [ -d "$pydir/polyloc" ]; then
  kill -TERM "$nav_pid"
  wait "$nav_pid" || true
  PYTHONPATH="$pydir" "$PY" - "$instance" <<'PYEOF'
import sys
from polyloc import shm
seg = shm.Segment.attach(sys.argv[1])
frames = shm.Reader(seg, "cmd_vel", start="oldest").drain()
assert len(frames) > 2, frames
last, before = frames[-1], frames[-2]
assert last["status"] == "polynav stopped" and last["twist"] == (0.0, 0.0, 0.0), last
assert last["stamp_ns"] > before["stamp_ns"], (before, last)
print("stop after SIGTERM:", last["stamp_ns"] - before["stamp_ns"], "ns after the last command")
PYEOF
else
  echo "skipped the stop-after-SIGTERM check: no Python module in $pydir"
fi

# Errors name what is wrong.
if "$POLYLOC" play --shm "$instance" --drive --input /dev/null 2> "$tmp/err"; then echo "--drive without scenario ran" >&2; exit 1; fi
grep -q "\-\-drive needs --scenario" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
if "$BIN/polynav" --shm "$instance" --grid "$tmp/nav.yaml" --zones maps/nav/lab.yaml --goals "no such goal" 2> "$tmp/err"; then
  echo "unknown goal accepted" >&2; exit 1
fi
grep -q "no goal 'no such goal'" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
if "$BIN/polynav" --shm nosuch_$$ --grid "$tmp/nav.yaml" --zones maps/nav/lab.yaml --goals "lab 1 bench" --wait 0.2 2> "$tmp/err"; then
  echo "polynav ran without polylocd" >&2; exit 1
fi
grep -q "polyloc.nosuch_$$" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
# A footprint with no area would make every pose look clear.
if "$BIN/polynav" --shm nosuch_$$ --grid "$tmp/nav.yaml" --zones maps/nav/lab.yaml --goals "lab 1 bench" --wait 0.2 \
    --footprint "0,0;0.5,0;1,0" 2> "$tmp/err"; then
  echo "polynav took a footprint with no area" >&2; exit 1
fi
grep -q "footprint '0,0;0.5,0;1,0': the polygon" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
echo "closed loop ok"
