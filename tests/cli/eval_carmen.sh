#!/usr/bin/env bash
# polyloc eval carmen on one shared real log (../shared/data/carmen), the defaults (no config),
# against the figures measured with the same command (tests/cli/eval_carmen_expected.json): the
# floor within 30 %, ATE / p95 / worst frame of each variant and its ratio to the floor at most
# 1.4x the measured (a 1.5x regression fails), no relocalisation, the global trials that
# succeeded at most one fewer (or 1.5x the failures); the run twice gives the same JSON, the PNG
# is a picture with the paths drawn. Usage: eval_carmen.sh POLYLOC SRC LOG
set -euo pipefail
polyloc=$1 src=$2 name=$3
log="$src/../shared/data/carmen/$name-corrected.log.gz"
[ -f "$log" ] || { echo "missing $log (the shared real logs)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
expected="$src/tests/cli/eval_carmen_expected.json"
args=$(python3 -c 'import json,sys; print(" ".join(json.load(open(sys.argv[1]))[sys.argv[2]]["args"]))' "$expected" "$name")
# shellcheck disable=SC2086
"$polyloc" eval carmen --log "$log" $args --json --plot "$tmp/eval.png" >"$tmp/a.json" 2>"$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
args_b=$(echo "$args" | sed 's/--global-trials [0-9]*//')
# shellcheck disable=SC2086
"$polyloc" eval carmen --log "$log" $args_b --json --no-floor --global-trials 0 >"$tmp/b.json" 2>"$tmp/err_b" || { cat "$tmp/err_b" >&2; exit 1; }
python3 - "$tmp/a.json" "$tmp/b.json" "$expected" "$name" "$tmp/eval.png" <<'PY'
import json, math, sys, zlib, struct
a, b, exp_all, name, png = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), sys.argv[4], sys.argv[5]
e = exp_all[name]
print(json.dumps({"floor": a["floor"]["ate_rmse_m"], **{v: a["variants"][v].get("ate_rmse_m") for v in a["variants"]},
                  "global": a["global"]["succeeded"]}))
def le(what, got, want, factor=1.4):
    assert got is not None and got <= factor * want, f"{name} {what}: {got} > {factor} x {want}"
f = a["floor"]["ate_rmse_m"]
assert 0.7 * e["floor_m"] <= f <= 1.3 * e["floor_m"], f"{name} floor {f} vs {e['floor_m']}"
for v, ev in e["variants"].items():
    got = a["variants"][v]
    if "unusable" in ev:
        assert ev["unusable"] in got.get("unusable", ""), (v, got.get("unusable"))
        continue
    for key in ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor"):
        le(f"{v} {key}", got[key], ev[key])
    assert got["counters"]["relocalizations"] <= ev["relocalizations"], (v, got["counters"]["relocalizations"])
    # Same input, config and seed: the same estimates (the second run skipped floor and global).
    assert got["ate_rmse_m"] == b["variants"][v]["ate_rmse_m"] and got["frames"] == b["variants"][v]["frames"], v
g, eg = a["global"], e["global"]
fail, efail = g["trials"] - g["succeeded"], eg["trials"] - eg["succeeded"]
assert g["trials"] == eg["trials"] and fail <= max(efail + 1, math.floor(1.5 * efail)), f"{name} global {g['succeeded']}/{g['trials']} vs {eg['succeeded']}"
# The picture: a PNG whose pixels are not all one colour (paths, map and legend drawn).
data = open(png, "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
w, h = struct.unpack(">II", data[16:24])
assert w > 500 and h > 500, (w, h)
PY
