#!/usr/bin/env bash
# The real-log robustness matrix, reduced (docs/localization.md "Real logs: the robustness
# matrix"): two shared logs, two map styles (polyloc's extrusion and the end-point map whose walls
# stand up to a cell proud), two drift levels (5 %/1 deg per m and 10 %/2 deg per m), every scan
# and every 2nd, on a prefix of each log. Against tests/cli/carmen_matrix_expected.json (measured
# with the same commands): per case ATE, p95 and ATE / floor at most 1.4x the measured (a 1.5x
# regression fails), no relocalisation where there was none; on the proud-walled map with 10 %
# drift no frame published as tracking is beyond 0.5 m of the truth and no jump goes unannounced;
# the strips picture shows one panel per case. Usage: carmen_matrix.sh POLYLOC SRC
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
expected="$src/tests/cli/carmen_matrix_expected.json"
for name in aces freiburg-101; do
  log="$src/../shared/data/carmen/$name-corrected.log.gz"
  [ -f "$log" ] || { echo "missing $log (the shared real logs)" >&2; exit 1; }
  args=$(python3 -c 'import json,sys; print(" ".join(json.load(open(sys.argv[1]))[sys.argv[2]]["args"]))' "$expected" "$name")
  # shellcheck disable=SC2086
  "$polyloc" eval carmen --log "$log" $args --json --strips "$tmp/$name.png" >"$tmp/$name.json" 2>"$tmp/$name.err" ||
    { cat "$tmp/$name.err" >&2; exit 1; }
  python3 - "$tmp/$name.json" "$expected" "$name" <<'PY'
import json, sys
got, exp_all, name = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
e = exp_all[name]
cases = {c["name"]: c for c in got["cases"]}
print(name, json.dumps({n: [round(c["ate_rmse_m"], 4), round(c["ate_over_floor"], 2), c["frames_tracking_beyond_0_5m"]] for n, c in cases.items()}))
assert sorted(cases) == sorted(e["cases"]), (sorted(cases), sorted(e["cases"]))
for n, ev in e["cases"].items():
    c = cases[n]
    for key in ("ate_rmse_m", "p95_pos_err_m", "ate_over_floor"):
        assert c[key] is not None and c[key] <= 1.4 * ev[key], f"{name} {n} {key}: {c[key]} > 1.4 x {ev[key]}"
    assert c["counters"]["relocalizations"] <= ev["relocalizations"], (name, n, c["counters"]["relocalizations"])
    assert c["frames_tracking_beyond_0_5m"] <= ev["frames_tracking_beyond_0_5m"], (name, n, c["frames_tracking_beyond_0_5m"])
    assert c["unannounced_jumps"] <= ev["unannounced_jumps"], (name, n, c["unannounced_jumps"])
# A proud-walled map and 10 % drift: never confidently wrong on aces (on freiburg-101 one frame
# of every 2nd scan is, 0.5-0.6 m off: docs/localization.md "What the matrix found").
for n in ("endpoint/high/x1", "endpoint/high/x2"):
    c = cases[n]
    if name == "aces":
        assert c["frames_tracking_beyond_0_5m"] == 0 and c["unannounced_jumps"] == 0, (name, n, c["worst_tracking_err_m"])
    assert c["range_bias_m"] > 0.01, (name, n, c["range_bias_m"])  # the proud walls were found
maps = {m["style"]: m for m in got["maps"]}
assert maps["endpoint"]["floor"]["range_bias_m"] > 0.01 and abs(maps["polyloc"]["floor"]["range_bias_m"]) < 0.015, maps
PY
  # 4 rows (map style x decimation) x 2 columns (drift) of panels (340 x 130 px each); every panel has points in the status
  # colours (tracking green) and the dashed 0.5 m line (red).
  python3 "$src/tests/tools/png_check.py" "$tmp/$name.png" --min-size 750x500 --colour tracking=1EA03C:30:1500 \
    --colour limit=DC2828:30:300
done
