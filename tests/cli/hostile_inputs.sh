#!/bin/bash
# docs/failure.md, as a hostile-but-fair user tries it: the values {0, -0, tiny, 1e19, 1e300,
# -1e300, inf, nan} in every numeric option of localize, play and polylocd --init, and in every
# field of SETPOSE against a running polylocd. No process dies of a signal; a value outside its
# domain is refused with a message naming the option; nothing written before is lost (an
# existing output stays whole); outputs that are inputs are refused; polylocd lives on, and 300
# idle connections to its live port do not keep its control endpoint from answering.
set -uo pipefail
POLYLOC=$1
SRC=$2
POLYLOCD=$(dirname "$POLYLOC")/polylocd
cd "$SRC"
tmp=$(mktemp -d)
instance=hostile_$$
pid=
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp" /dev/shm/polyloc.$instance /dev/shm/polyloc.${instance}_b /dev/shm/polyloc.${instance}_c' EXIT
VALUES="0 -0 1e-300 1e19 1e300 -1e300 inf nan"
fail() { echo "FAIL: $*" >&2; exit 1; }
in_domain() {  # value, lo, hi: finite and within
  python3 -c "import math,sys; v=float(sys.argv[1]); sys.exit(0 if math.isfinite(v) and $2 <= v <= $3 else 1)" "$1"
}

"$POLYLOC" simulate --scenario maps/scenarios/lab_tour.yaml --duration 1.5 --out "$tmp/run.mcap" > /dev/null 2>&1 \
  || fail "simulate"
cp "$tmp/run.mcap" "$tmp/run.orig"
echo "# an earlier estimate that must survive" > "$tmp/est.tum"
cp "$tmp/est.tum" "$tmp/est.orig"

# localize --init / --init-sigma: each position of each option.
checked=0
for v in $VALUES; do
  for spec in "--init $v,1.75,0:0:-10.4:36.4" "--init 1.3,$v,0:0:-10.4:24.4" "--init 1.3,1.75,$v:0:-5729:5729" \
              "--init-sigma $v,5:1:0:1000" "--init-sigma 0.1,$v:1:0:5729"; do
    IFS=: read -r opt sigma lo hi <<< "$spec"
    args=($opt)
    [ "$sigma" = 1 ] && args=(--init 1.3,1.75,0 "${args[@]}")
    "$POLYLOC" localize --config maps/config/lab.yaml --input "$tmp/run.mcap" --out "$tmp/est.tum" "${args[@]}" \
      > /dev/null 2> "$tmp/err"
    rc=$?
    [ $rc -lt 128 ] || fail "localize ${args[*]}: killed by a signal (rc $rc)"
    if in_domain "$v" "$lo" "$hi"; then
      [ $rc -eq 0 ] || { cat "$tmp/err" >&2; fail "localize ${args[*]}: refused a value in the domain"; }
      cp "$tmp/est.orig" "$tmp/est.tum"
    else
      [ $rc -eq 1 ] || fail "localize ${args[*]}: rc $rc, expected 1"
      grep -q -- "${opt%% *}" "$tmp/err" || { cat "$tmp/err" >&2; fail "localize ${args[*]}: the error does not name the option"; }
      cmp -s "$tmp/est.tum" "$tmp/est.orig" || fail "localize ${args[*]}: the earlier output was touched"
    fi
    checked=$((checked + 1))
  done
done
cmp -s "$tmp/run.mcap" "$tmp/run.orig" || fail "the recording changed"

# Outputs never destroy inputs, and unwritable outputs fail before the run.
if "$POLYLOC" localize --config maps/config/lab.yaml --input "$tmp/run.mcap" --out "$tmp/../$(basename "$tmp")/run.mcap" 2> "$tmp/err"; then
  fail "--out = --input accepted"
fi
grep -q "refusing to overwrite" "$tmp/err" || { cat "$tmp/err" >&2; fail "no reason for --out = --input"; }
cmp -s "$tmp/run.mcap" "$tmp/run.orig" || fail "the recording was overwritten"
if "$POLYLOC" localize --config maps/config/lab.yaml --input "$tmp/run.mcap" --out "$tmp/a.tum" --csv "$tmp/a.tum" 2> "$tmp/err"; then
  fail "two outputs on one file accepted"
fi
if "$POLYLOC" localize --config maps/config/lab.yaml --input "$tmp/run.mcap" --out /proc/x.tum 2> "$tmp/err"; then
  fail "/proc/x.tum accepted"
fi
grep -q "/proc/x.tum" "$tmp/err" || { cat "$tmp/err" >&2; fail "no reason for /proc/x.tum"; }
if "$POLYLOC" localize --config maps/config/office.yaml --input "$tmp/run.mcap" 2> "$tmp/err"; then
  fail "a recording with no topic of the rig accepted"
fi
grep -q "no topic matches a sensor of rig" "$tmp/err" || { cat "$tmp/err" >&2; fail "no reason for the rig mismatch"; }
[ -z "$(ls -A "$tmp" | grep partial)" ] || fail "a temporary output was left behind"

# play's options: refused as usage errors (exit 2), never a crash or "plays everything".
for v in $VALUES -5; do
  for opt in --duration --rate --wait; do
    "$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --wait 0 "$opt" "$v" > /dev/null 2> "$tmp/err"
    rc=$?
    [ $rc -lt 128 ] || fail "play $opt $v: killed by a signal"
    [ $rc -ne 0 ] || fail "play $opt $v without polylocd: exit 0"
  done
done
"$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --wait 0 --duration -5 2> "$tmp/err"
[ $? -eq 2 ] || fail "--duration -5: expected a usage error (2)"

# polylocd --init off the map or not a number: refused at start, exit 1, nothing left "starting".
for v in 1e19 1e300 -1e300 inf nan; do
  for init in "$v,1.75,0" "1.3,$v,0" "1.3,1.75,$v"; do
    "$POLYLOCD" --config maps/config/lab.yaml --instance "${instance}_b" --control-port 0 --init "$init" 2> "$tmp/err" > /dev/null
    rc=$?
    [ $rc -eq 1 ] || { cat "$tmp/err" >&2; fail "polylocd --init $init: rc $rc, expected 1"; }
    grep -q "init" "$tmp/err" || { cat "$tmp/err" >&2; fail "polylocd --init $init: no reason"; }
  done
done
if "$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "${instance}_b" --wait 0.3 --duration 1 2> "$tmp/err"; then
  fail "play against a failed start succeeded"
fi
grep -q "stopped\|No such file" "$tmp/err" || { cat "$tmp/err" >&2; fail "a failed start left a segment that does not say so"; }

# SETPOSE: every value in every field against a running daemon; it lives and keeps its pose.
"$POLYLOCD" --config maps/config/lab.yaml --instance "$instance" --control-port 0 --init 1.3,1.75,0 --threads 2 \
  2> "$tmp/polylocd.log" &
pid=$!
for i in $(seq 100); do
  port=$(sed -n 's/.*control endpoint on 127.0.0.1:\([0-9]*\).*/\1/p' "$tmp/polylocd.log" | head -1)
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { cat "$tmp/polylocd.log" >&2; fail "polylocd did not start"; }
refused=0
for v in $VALUES; do
  for args in "$v 1.75 0" "1.3 $v 0" "1.3 1.75 $v" "1.3 1.75 0 $v 5" "1.3 1.75 0 0.1 $v"; do
    "$POLYLOC" ctl --port "$port" setpose $args > /dev/null 2> "$tmp/err"
    rc=$?
    [ $rc -lt 128 ] || fail "ctl setpose $args: killed by a signal"
    if [ $rc -ne 0 ]; then
      grep -q "bad_argument\|not a number\|not a finite" "$tmp/err" || { cat "$tmp/err" >&2; fail "setpose $args: $(cat "$tmp/err")"; }
      refused=$((refused + 1))
    fi
    kill -0 $pid 2> /dev/null || { tail "$tmp/polylocd.log" >&2; fail "polylocd died after setpose $args"; }
  done
done
"$POLYLOC" ctl --port "$port" ping > /dev/null || fail "polylocd does not answer after the sweep"
grep -q "SETPOSE refused: x is 1e+19" "$tmp/polylocd.log" || { cat "$tmp/polylocd.log" >&2; fail "no reason logged for x 1e19"; }
# Finite but beyond the domain (1e19, +-1e300 as float: inf) and inf/nan refused in each field;
# a spread of 0 or -0 means "the default" on the wire, tiny is a spread.
[ "$refused" -ge 25 ] || fail "only $refused of the 25 out-of-domain SETPOSE values were refused"
"$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --duration 2 --json --quiet > "$tmp/play.json" \
  || fail "play after the sweep"
python3 - "$tmp/play.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["answered"] and j["poses"] > 3, j
assert j["accuracy"]["p95_pos_err_m"] < 0.1, j["accuracy"]
fit = [v["map_fit"] for v in j["polylocd"]["inputs"].values() if v["map_fit"] is not None]
assert fit and min(fit) > 0.5, fit  # the simulated lab fits its own map
PYEOF
"$POLYLOC" ctl --port "$port" status --json > "$tmp/status.json" || fail "ctl status"
python3 - "$tmp/status.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
fit = {i["name"]: i["map_fit"] for i in j["inputs"]}
assert j["unfit"] is False and fit["odom"] is None and fit["scan/s300_front_left"] > 0.5, j
PYEOF
kill -TERM $pid
wait $pid
pid=

# Idle TCP connections to the live port: 300 of them against a polylocd allowed 128 file
# descriptors (they once used them all up: "accept failed: Too many open files", the control
# endpoint stopped answering). Pending connections are bounded; the control endpoint answers.
lport=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
( ulimit -n 128; exec "$POLYLOCD" --config maps/config/lab.yaml --instance "${instance}_c" --control-port 0 \
    --live-port "$lport" --init 1.3,1.75,0 --threads 2 2> "$tmp/polylocd_c.log" ) &
pid=$!
cport=
for i in $(seq 100); do
  cport=$(sed -n 's/.*control endpoint on 127.0.0.1:\([0-9]*\).*/\1/p' "$tmp/polylocd_c.log" | head -1)
  [ -n "$cport" ] && grep -q "live view on" "$tmp/polylocd_c.log" && break
  sleep 0.1
done
[ -n "$cport" ] || { cat "$tmp/polylocd_c.log" >&2; fail "polylocd (128 descriptors) did not start"; }
python3 - "$lport" "$POLYLOC" "$cport" <<'PYEOF' || fail "the control endpoint under idle live connections"
import socket, subprocess, sys, time
lport, polyloc, cport = int(sys.argv[1]), sys.argv[2], sys.argv[3]
held = []
for _ in range(300):
    try:
        held.append(socket.create_connection(("127.0.0.1", lport), timeout=2))
    except OSError:
        pass  # refused or reset: as good
time.sleep(0.5)
for k in range(3):  # three pings while the connections are held
    r = subprocess.run([polyloc, "ctl", "--port", cport, "ping"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, (k, r.stdout, r.stderr)
print("control endpoint answered with", len(held), "idle live connections opened")
PYEOF
grep -q "max_pending" "$tmp/polylocd_c.log" || { cat "$tmp/polylocd_c.log" >&2; fail "no warning about pending live connections"; }
if grep -q "Too many open files" "$tmp/polylocd_c.log"; then fail "polylocd ran out of file descriptors"; fi
kill -0 $pid || fail "polylocd died under idle live connections"
kill -TERM $pid
wait $pid
pid=
echo "hostile inputs ok: $checked localize values, $refused SETPOSE values refused, polylocd alive"
