#!/usr/bin/env bash
# polyloc bench maps as a user runs it: the run of docs/benchmarks.md "Map representations" (lab,
# 5 cm, 100,000 rays, seed 1; one timed repetition instead of three: the errors do not depend on
# it) with every backend and the documented keys; the BSP agrees with Embree as claimed (planar
# median and p99 0, i.e. within 1 mm; 3D median within 1 mm), the other backends' range errors
# within 1.5x of the claimed figures; a Markdown table; MCL with the 2D grid tracks the lab tour;
# errors that name the bad input.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$polyloc" bench maps --map "$src/maps/lab.obj" --threads 2 --repeat 1 --json --markdown "$tmp/table.md")
echo "$out"
python3 - "$out" <<'PY'
import json, math, sys
j = json.loads(sys.argv[1])
b = j["backends"]
assert j["rays"] == 100000 and abs(j["resolution_m"] - 0.05) < 1e-9 and j["triangles"] == 6760, j
for name in ("embree", "bsp", "grid2d", "distance3d", "octomap"):
    assert name in b, name
    for key in ("build_s", "memory_mb", "rays_per_s_planar", "rays_per_s_3d", "point_queries_per_s",
                "range_err_mean_m", "range_err_median_m", "range_err_p99_m",
                "range_err_3d_mean_m", "range_err_3d_median_m", "range_err_3d_p99_m"):
        v = b[name][key]
        assert isinstance(v, (int, float)) and math.isfinite(v) and v >= 0, (name, key, v)
    assert b[name]["rays_per_s_planar"] > 0
e = b["embree"]   # the reference against itself
assert all(e[k] == 0 for k in e if k.startswith("range_err")), e
failures = []
def at_most(name, key, bound, why):
    v = b[name][key]
    if not v <= bound:
        failures.append(f"{name} {key} = {v:.6g} > {bound:.6g} ({why})")
# The BSP is exact: docs/benchmarks.md, planar median / p99 0.000 / 0.000 m and the same hits.
# Its 3D p99 (2.129 m) and the means (0.018 / 0.055 m) come from origins inside overlapping
# solids (these origins are not filtered to free space), bounded at 1.5x; from free origins the
# two agree on 100 % of the rays within 1 mm: tests/cli/bench_bsp.sh.
for key in ("range_err_median_m", "range_err_p99_m", "range_err_3d_median_m"):
    at_most("bsp", key, 0.001, "exact: within 1 mm of Embree")
at_most("bsp", "range_err_hit_disagreement", 0.0, "the BSP and Embree hit the same planar rays")
at_most("bsp", "range_err_mean_m", 1.5 * 0.018, "1.5x the claimed 0.018 m")
at_most("bsp", "range_err_3d_mean_m", 1.5 * 0.055, "1.5x the claimed 0.055 m")
at_most("bsp", "range_err_3d_p99_m", 1.5 * 2.129, "1.5x the claimed 2.129 m")
# The approximations, 1.5x of docs/benchmarks.md's table (same run): planar mean / median / p99,
# 3D mean / median / p99. The medians are each representation's resolution (distance3d 1.2 cm,
# grid2d 2.6 cm, octomap 3.1 cm); the means and p99 are the near-miss tail.
claimed = {
    "distance3d": (0.385, 0.012, 7.284, 0.062, 0.004, 1.067),
    "grid2d": (0.448, 0.026, 7.516, 2.522, 0.113, 23.808),
    "octomap": (0.491, 0.031, 7.566, 0.148, 0.055, 2.522),
}
keys = ("range_err_mean_m", "range_err_median_m", "range_err_p99_m",
        "range_err_3d_mean_m", "range_err_3d_median_m", "range_err_3d_p99_m")
for name, figures in claimed.items():
    for key, c in zip(keys, figures):
        at_most(name, key, 1.5 * c, f"1.5x the claimed {c} m")
# The GPU caster (with POLYLOC_GPU; llvmpipe in CI): exact like the BSP on planar rays; in 3D the
# rays from inside overlapping solids are facing ties (docs/benchmarks.md: 3D mean 0.020 m, hit
# disagreement 0.11%, point agreement 99.85%).
if "gpu" in b:
    for key in ("range_err_median_m", "range_err_p99_m", "range_err_3d_median_m"):
        at_most("gpu", key, 0.001, "float32 on a BVH: within 1 mm of Embree")
    at_most("gpu", "range_err_hit_disagreement", 0.0005, "the same planar hits")
    at_most("gpu", "range_err_3d_mean_m", 1.5 * 0.020, "1.5x the claimed 0.020 m")
    at_most("gpu", "range_err_3d_hit_disagreement", 1.5 * 0.0011, "1.5x the claimed 0.11%")
    if not b["gpu"]["point_agreement"] >= 0.997:
        failures.append(f"gpu point_agreement {b['gpu']['point_agreement']} < 0.997")
assert not failures, "\n".join(failures)
print("bench maps: BSP exact; distance3d / grid2d / octomap planar medians",
      [round(b[n]["range_err_median_m"], 4) for n in claimed], "within 1.5x of", [c[1] for c in claimed.values()])
PY
grep -q '| grid2d |' "$tmp/table.md"
grep -q '| bsp |' "$tmp/table.md"
# MCL weighing with the 2D grid tracks the lab tour on the level scanners (mcl.caster grid2d).
# 8 s of the tour, not the documented 30 s (about 2 s here instead of 6): measured here 13.3 mm
# mean, 21.5 mm p95, 0.186 deg mean yaw error, the same on every run (seeded); bounds at 1.5x
# of those (the documented 30 s run: 15 / 28 mm, 0.19 deg).
out=$("$polyloc" bench maps --map "$src/maps/lab.obj" --backends grid2d --rays 200 --beams 10 --repeat 1 \
  --localize "$src/maps/scenarios/lab_tour.yaml" --localize-duration 8 --json)
python3 - "$out" <<'PY'
import json, sys
l = json.loads(sys.argv[1])["backends"]["grid2d"]["localize"]
print("grid2d MCL:", {k: l[k] for k in ("trans_err_mean_m", "trans_err_p95_m", "yaw_err_mean_deg", "updates")})
assert l["sensors"] == ["s300_front_left", "s300_rear_right"], l["sensors"]
assert abs(l["slice_height_m"] - 0.10) < 1e-9, l
assert l["final_status"] == "tracking", l
assert l["updates"] >= 50, l
assert l["trans_err_mean_m"] <= 1.5 * 0.0133, ("trans_err_mean_m", l["trans_err_mean_m"], "1.5x 13.3 mm")
assert l["trans_err_p95_m"] <= 1.5 * 0.0215, ("trans_err_p95_m", l["trans_err_p95_m"], "1.5x 21.5 mm")
assert l["yaw_err_mean_deg"] <= 1.5 * 0.186, ("yaw_err_mean_deg", l["yaw_err_mean_deg"], "1.5x 0.186 deg")
PY
# An unknown backend is an error that lists the known ones.
if err=$("$polyloc" bench maps --map "$src/maps/office.obj" --backends embree,nosuch --rays 100 --json 2>&1); then exit 1; fi
grep -q "nosuch" <<<"$err"
grep -q "grid2d" <<<"$err"
echo OK
