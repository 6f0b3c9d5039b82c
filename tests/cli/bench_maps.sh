#!/usr/bin/env bash
# polyloc bench maps as a user runs it, with small numbers: one JSON object with every backend
# and the documented keys, a Markdown table, and errors that name the bad input.
set -euo pipefail
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$polyloc" bench maps --map "$src/maps/office.obj" --rays 2000 --beams 20 --resolution 0.1 \
  --threads 2 --repeat 1 --json --markdown "$tmp/table.md")
echo "$out"
python3 - "$out" <<'PY'
import json, math, sys
j = json.loads(sys.argv[1])
b = j["backends"]
for name in ("embree", "bsp", "grid2d", "distance3d", "octomap"):
    assert name in b, name
    for key in ("build_s", "memory_mb", "rays_per_s_planar", "rays_per_s_3d", "point_queries_per_s",
                "range_err_mean_m", "range_err_p99_m"):
        v = b[name][key]
        assert isinstance(v, (int, float)) and math.isfinite(v) and v >= 0, (name, key, v)
    assert b[name]["rays_per_s_planar"] > 0
assert b["embree"]["range_err_mean_m"] == 0
# Planar rays at 10 cm: the mean is dominated by near misses (rays within a cell of a chair leg).
for name in ("bsp", "grid2d", "distance3d", "octomap"):
    assert b[name]["range_err_mean_m"] < 1.0, (name, b[name]["range_err_mean_m"])
PY
grep -q '| grid2d |' "$tmp/table.md"
# MCL weighing with the 2D grid tracks the lab tour on the level scanners (mcl.caster grid2d).
out=$("$polyloc" bench maps --map "$src/maps/lab.obj" --backends grid2d --rays 200 --beams 10 --repeat 1 \
  --localize "$src/maps/scenarios/lab_tour.yaml" --localize-duration 8 --json)
python3 - "$out" <<'PY'
import json, sys
l = json.loads(sys.argv[1])["backends"]["grid2d"]["localize"]
assert l["sensors"] == ["s300_front_left", "s300_rear_right"], l["sensors"]
assert abs(l["slice_height_m"] - 0.10) < 1e-9, l
assert l["final_status"] == "tracking", l
assert l["updates"] > 20 and l["trans_err_mean_m"] < 0.08, l
PY
# An unknown backend is an error that lists the known ones.
if err=$("$polyloc" bench maps --map "$src/maps/office.obj" --backends embree,nosuch --rays 100 --json 2>&1); then exit 1; fi
grep -q "nosuch" <<<"$err"
grep -q "grid2d" <<<"$err"
echo OK
