#!/bin/bash
# polyloc eval depth: a short lab tour; the JSON has the documented fields and the defaults meet
# the bounds; a standalone depth_filter file is read; bad keys are errors naming the key.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
PY=$(command -v python3)
cd "$SRC"
out=$("$POLYLOC" eval depth --scenario maps/scenarios/lab_tour.yaml --duration 20 --json)
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["sensor"] == "tof_front" and j["frames"] == 401, j
assert j["depth_outlier_removed"] >= 0.95 and j["depth_valid_kept"] >= 0.95, j
assert set(j["per_filter"]) == {"validity", "jump_edge", "confidence"}, j
for f in j["per_filter"].values():
    assert 0 <= f["outlier_removed"] <= 1 and 0 <= f["valid_kept"] <= 1, f
print("eval depth ok:", j["depth_outlier_removed"], j["depth_valid_kept"])
'
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'depth_filter:\n  confidence: {enabled: false}\n  jump_edge: {enabled: false}\n' > "$tmp/off.yaml"
out=$("$POLYLOC" eval depth --scenario maps/scenarios/lab_tour.yaml --duration 5 --config "$tmp/off.yaml" --json)
echo "$out" | "$PY" -c '
import json, sys
j = json.load(sys.stdin)
assert j["depth_outlier_removed"] < 0.05, j   # validity alone removes next to nothing
'
printf 'depth_filter:\n  confidence: {treshold: 0.5}\n' > "$tmp/bad.yaml"
if "$POLYLOC" eval depth --scenario maps/scenarios/lab_tour.yaml --config "$tmp/bad.yaml" 2> "$tmp/err"; then
  echo "a misspelt key was accepted"; exit 1
fi
grep -q "treshold" "$tmp/err" && grep -q "bad.yaml:2" "$tmp/err"
echo "eval depth: ok"
