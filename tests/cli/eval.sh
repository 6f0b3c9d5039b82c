#!/bin/bash
# polyloc eval global|kidnap: a few short trials on the bundled lab; the JSON has the documented
# fields; the trials succeed as docs/benchmarks.md says they do (global: every start within 2
# rounds, the median and worst of 50 are 1 and 2; kidnap: recovered), to a few millimetres; bad
# options are errors that name the option. The trials are seeded: the same answer every run.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
PY=$(command -v python3)
cd "$SRC"
out=$("$POLYLOC" eval global --scenario maps/scenarios/lab_tour.yaml --trials 2 --rounds 5 --hold 3 --global-particles 20000 --json)
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["mode"] == "global" and j["trials"] == 2, j
assert j["succeeded"] == 2 and j["fraction"] == 1.0, j
assert j["rounds_allowed"] == 5 and j["particles"] == 20000, j
for r in j["results"]:
    assert r["rounds"] == 8, r              # rounds + hold: the drive is long enough
    assert r["converged"] and 0 < r["converged_round"] <= 3, r    # worst of 50 is 2 (x1.5)
    assert 0 <= r["final_pos_err_m"] < 0.015 and abs(r["final_yaw_err_deg"]) < 0.5, r
print("global ok:", j["succeeded"], "of", j["trials"])
'
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$POLYLOC" eval kidnap --scenario maps/scenarios/lab_tour.yaml --trials 1 --kidnap-after 5 --rounds 10 --hold 2 --json --plot "$tmp/k.png")
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["mode"] == "kidnap" and j["trials"] == 1 and j["kidnap_after_rounds"] == 5, j
r = j["results"][0]
assert r["rounds"] == 12, j
assert j["succeeded"] == 1 and r["converged"] and r["final_pos_err_m"] < 0.015, j  # recovered, to mm
print("kidnap ok")
'
# The plot (cmd_eval.cpp): the lab slice and each trial's start, green when it converged (red
# otherwise; the map has 253 red pixels of its own and no green): 221 green pixels here.
"$PY" tests/tools/png_check.py "$tmp/k.png" --min-size 1000x600 --min-colours 200 --ink 0.03,0.3 \
  --colour converged_start=1EA03C:40:110
if "$POLYLOC" eval global --scenario maps/scenarios/lab_tour.yaml --trials 0 2> "$tmp/err"; then
  echo "--trials 0 was accepted"; exit 1
fi
grep -q -- "--trials" "$tmp/err"
if "$POLYLOC" eval global --scenario /nonexistent.yaml 2> "$tmp/err"; then echo "missing scenario accepted"; exit 1; fi
grep -q "nonexistent" "$tmp/err"
echo "eval: ok"
