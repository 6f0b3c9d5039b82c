#!/bin/bash
# polyloc eval global|kidnap: a few short trials on the bundled lab; the JSON has the documented
# fields and sane values; bad options are errors that name the option.
set -euo pipefail
POLYLOC=$1
SRC=$2
PY=$(command -v python3)
cd "$SRC"
out=$("$POLYLOC" eval global --scenario maps/scenarios/lab_tour.yaml --trials 2 --rounds 5 --hold 3 --particles 20000 --json)
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["mode"] == "global" and j["trials"] == 2, j
assert 0 <= j["succeeded"] <= 2 and j["fraction"] == j["succeeded"] / 2, j
assert j["rounds_allowed"] == 5 and j["particles"] == 20000, j
for r in j["results"]:
    assert r["rounds"] == 8, r              # rounds + hold: the drive is long enough
    assert r["final_pos_err_m"] >= 0 and r["converged"] == (0 < r["converged_round"] <= 5), r
print("global ok:", j["succeeded"], "of", j["trials"])
'
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$POLYLOC" eval kidnap --scenario maps/scenarios/lab_tour.yaml --trials 1 --kidnap-after 5 --rounds 10 --hold 2 --json --plot "$tmp/k.png")
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["mode"] == "kidnap" and j["trials"] == 1 and j["kidnap_after_rounds"] == 5, j
assert j["results"][0]["rounds"] == 12, j
print("kidnap ok")
'
test -s "$tmp/k.png"
if "$POLYLOC" eval global --scenario maps/scenarios/lab_tour.yaml --trials 0 2> "$tmp/err"; then
  echo "--trials 0 was accepted"; exit 1
fi
grep -q -- "--trials" "$tmp/err"
if "$POLYLOC" eval global --scenario /nonexistent.yaml 2> "$tmp/err"; then echo "missing scenario accepted"; exit 1; fi
grep -q "nonexistent" "$tmp/err"
echo "eval: ok"
