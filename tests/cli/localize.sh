#!/usr/bin/env bash
# polyloc localize, as a user types it: 20 s of the office patrol simulated, localised from the
# first ground-truth pose with --json (keys; ATE, p95 and p95 yaw within 1.5x of the office figures
# of docs/benchmarks.md), the TUM, CSV and PNG outputs (png_check: truth and estimate drawn); a
# CARMEN log with bad scans (rejected, counted, no crash), also on a rig without scanners; a
# missing input (exit 1 naming the path). ramp_6dof's figures: localize_ramp.sh.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
"$polyloc" simulate --scenario maps/scenarios/office_patrol.yaml --duration 20 --out "$tmp/run.mcap" >/dev/null
if ! out=$("$polyloc" localize --config maps/config/office.yaml --map maps/office.obj --input "$tmp/run.mcap" \
    --out "$tmp/traj.tum" --plot "$tmp/loc.png" --csv "$tmp/frames.csv" --json 2>"$tmp/err"); then
  cat "$tmp/err" >&2
  exit 1
fi
echo "$out"
grep -q "first ground-truth pose" "$tmp/err"
python3 - "$out" "$tmp/traj.tum" "$tmp/frames.csv" <<'PY'
import json, math, sys
j = json.loads(sys.argv[1])
for key in ("frames", "updates", "updates_per_s", "wall_s", "ate_rmse_m", "p95_pos_err_m", "yaw_rmse_deg",
            "p95_yaw_err_deg", "z_rmse_m", "roll_pitch_rmse_deg", "converged_after_s", "after_convergence",
            "counters"):
    assert key in j, key
assert j["init"] == "ground_truth", j["init"]
# One frame (estimate) per round; a round weighs each of the rig's 2 scanners once.
assert j["updates"] > 10 and j["updates"] / 2 <= j["frames"] <= j["updates"], (j["updates"], j["frames"])
assert j["updates_per_s"] > 0 and j["wall_s"] > 0
# docs/benchmarks.md claims 0.07 cm ATE and 0.13 cm p95 on office_patrol (refined): 1.5x of each.
assert math.isfinite(j["ate_rmse_m"]) and j["ate_rmse_m"] < 0.0011, j["ate_rmse_m"]
assert j["p95_pos_err_m"] < 0.002, j["p95_pos_err_m"]
assert j["p95_yaw_err_deg"] <= 1.5 * 0.01, j["p95_yaw_err_deg"]   # 0.01 deg claimed (x1.5); 0.0094 here
assert j["converged_after_s"] is not None and j["converged_after_s"] < 5, j["converged_after_s"]
assert j["counters"]["scans_wrong_size"] == 0 and j["counters"]["scans_unknown_sensor"] == 0, j["counters"]
tum = [l for l in open(sys.argv[2]) if l.strip() and not l.startswith("#")]
assert len(tum) == j["frames"], (len(tum), j["frames"])
csv = open(sys.argv[3]).read().splitlines()
assert csv[0].startswith("stamp_ns,x,y,z,") and "pos_err_m" in csv[0], csv[0]
assert len(csv) == 1 + j["evaluated_frames"]
PY
# The plot (viz/localize_plot.cpp): truth blue, estimate red, particle clouds orange, magenta,
# cyan, brown. The office map itself has none of blue, red and magenta (a 0.5 s run's plot: 0
# pixels each); these 20 s give 465 blue, 396 red, 231 magenta pixels: half of each is required.
python3 tests/tools/png_check.py "$tmp/loc.png" --min-size 1000x1000 --min-colours 500 --ink 0.05,0.3 \
  --colour truth=285ADC:40:230 --colour estimate=DC1E1E:40:200 --colour cloud=C828A0:40:115
# The same run localised on a 2D grid (mcl.caster grid2d, sliced at the LMS200s' 0.20 m): a grid
# deployment of the same filter; a sensor the rig lacks is a config error naming file and line.
cat >"$tmp/grid.yaml" <<YAML
map: $src/maps/office.obj
robot: {footprint: [[0.35, 0.3], [-0.35, 0.3], [-0.35, -0.3], [0.35, -0.3]], height: 1.5, kinematics: differential}
rig: $src/maps/rigs/taser.yaml
mcl: {caster: grid2d, caster_resolution: 0.05, refine: {enabled: true}}
YAML
# No documented figure for it: measured here on these 20 s (seeded, the same every run) ATE 2.39 cm,
# p95 3.53 cm, p95 yaw 0.91 deg; bounds at 1.5x of those.
out=$("$polyloc" localize --config "$tmp/grid.yaml" --input "$tmp/run.mcap" --json 2>"$tmp/err")
python3 -c 'import json,sys; j=json.loads(sys.argv[1]); print("grid2d:", {k: j[k] for k in ("ate_rmse_m", "p95_pos_err_m", "p95_yaw_err_deg")})
assert j["updates"] > 10 and j["status"] == "tracking", j
assert j["ate_rmse_m"] <= 1.5 * 0.0239 and j["p95_pos_err_m"] <= 1.5 * 0.0353 and j["p95_yaw_err_deg"] <= 1.5 * 0.91, j' "$out"
sed -i 's/caster: grid2d, /caster: grid2d, sensors: [lms_front, lms_side], /' "$tmp/grid.yaml"
if "$polyloc" localize --config "$tmp/grid.yaml" --input "$tmp/run.mcap" 2>"$tmp/err"; then exit 1; fi
grep -q "grid.yaml:4:.*mcl.sensors.*'lms_side' is not in rig" "$tmp/err" || { cat "$tmp/err"; exit 1; }
# CARMEN: FLASER goes to the taser's first planar scanner, an LMS200 with 361 beams; FLASER
# with 3 ranges is rejected, counted and warned about once. With every scan rejected nothing was
# localised: the counts still go out, and the run is an error (it exited 0).
{
  for i in 0 1 2 3 4; do
    echo "ODOM 0.$i 0 0 0.1 0 0 100$i.0 host 0"
    echo "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 100$i.5 host 0"
  done
} >"$tmp/run.log"
rc=0
out=$("$polyloc" localize --config maps/config/office.yaml --input "$tmp/run.log" --init 1,1.5,0,90 --json 2>"$tmp/err") || rc=$?
[ "$rc" = 1 ] || { echo "exit $rc when every scan was rejected" >&2; exit 1; }
grep -q "no scan of $tmp/run.log was used, nothing was localised (5 rejected: 5 wrong size" "$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
python3 -c 'import json,sys; j=json.loads(sys.argv[1]); c=j["counters"]; assert c["scans_wrong_size"] == 5 and c["odometry"] == 5, c; assert "ate_rmse_m" not in j' "$out"
grep -q "/front_laser: 3 beams, .* recorded, sensor 'lms_front' has 361 beams" "$tmp/err"
[ "$(grep -c 'warning: /front_laser' "$tmp/err")" = 1 ]  # warned once
# A rig without planar scanners: the CARMEN laser has no sensor; warned once, and with no frame
# for any rig sensor the run is an error naming the recording's topics and the rig's sensors
# (docs/failure.md), not an empty success.
cat >"$tmp/cam.yaml" <<YAML
map: $src/maps/office.obj
robot: {footprint: [[0.3, 0.25], [-0.3, 0.25], [-0.3, -0.25], [0.3, -0.25]], height: 1.2, kinematics: differential}
rig: {name: cam_only, sensors: [{name: tof, preset: pmd_o3d100, mount: {x: 0.3, y: 0, z: 0.5, roll: 0, pitch: 0, yaw: 0}}]}
YAML
rc=0
"$polyloc" localize --config "$tmp/cam.yaml" --input "$tmp/run.log" --init 1,1.5,0,90 --json >/dev/null 2>"$tmp/err" || rc=$?
[ "$rc" = 1 ] || { echo "exit $rc for a recording with no topic of the rig" >&2; exit 1; }
[ "$(grep -c "/front_laser: no sensor of rig 'cam_only'" "$tmp/err")" = 1 ]
grep -q "no topic matches a sensor of rig 'cam_only' (the recording has /front_laser; the rig's sensors are tof)" "$tmp/err" \
  || { cat "$tmp/err" >&2; exit 1; }
# A missing input: exit 1, the message names the path.
rc=0
"$polyloc" localize --config maps/config/office.yaml --input "$tmp/missing.mcap" --out "$tmp/x.tum" 2>"$tmp/err" || rc=$?
[ "$rc" = 1 ] || { echo "exit $rc for a missing input" >&2; exit 1; }
grep -q "$tmp/missing.mcap" "$tmp/err"
echo OK
