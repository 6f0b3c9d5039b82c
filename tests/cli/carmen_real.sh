#!/usr/bin/env bash
# A real CARMEN log as a user meets it (../shared/data/carmen, docs/localization.md "Real logs"):
# info names the stamps that do not increase and the field of view written in radians, and
# --restamp gives a usable time; the even scans make a map (map extrude --scans even); localize
# takes the scanner from the log (no rig in the config), starts from the first ground-truth pose,
# writes times relative to the start (never negative), and gives byte-identical outputs on 1 and
# 2 threads and on a second run; a rig sensor whose geometry differs from the log's is named.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
data="$src/../shared/data/carmen"
[ -d "$data" ] || { echo "missing $data (the shared real logs)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
aces="$data/aces-corrected.log.gz" csail="$data/csail-corrected.log.gz"

# info: csail writes six-digit stamps and its fov in radians; orebro's scans are stamped 0.
"$polyloc" info "$csail" --json >"$tmp/csail.json"
"$polyloc" info "$csail" --restamp 10 --json >"$tmp/csail10.json"
"$polyloc" info "$csail" >"$tmp/csail.txt"
grep -q "duration:  unknown" "$tmp/csail.txt"
grep -q "laser_front_laser_fov 3.14159: taken as radians (180 deg)" "$tmp/csail.txt"
python3 - "$tmp/csail.json" "$tmp/csail10.json" <<'PY'
import json, sys
j, r = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert j["duration_s"] is None, j["duration_s"]
s = j["stamps_not_increasing"]["/front_laser"]
assert s["messages"] == 406 and s["equal"] == 404 and s["zero"] == 0, s  # 406 scans, 2 distinct stamps
assert j["topics"]["/front_laser"]["rate_hz"] is None
assert any("taken as radians" in n for n in j["notes"]), j["notes"]
# Restamped by order at 10 Hz: one message every 0.1 s, and nothing left to complain about.
assert r["stamps_not_increasing"] == {}, r["stamps_not_increasing"]
assert abs(r["duration_s"] - (r["messages"] - 1) / 10) < 1e-6, (r["duration_s"], r["messages"])
PY

# The map from the even scans, the odd ones localised as a user would: config naming only the
# robot (no rig: the scanner comes from the log), the log's own ODOM lines.
"$polyloc" map extrude --carmen "$aces" --scans even --out "$tmp/map.obj" --json >"$tmp/extrude.json"
python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); assert j["scans_used"] == 220 and j["skipped_reasons"] == {"not_selected": 220}, j' "$tmp/extrude.json"
python3 - "$aces" "$tmp/truth.tum" <<'PY'
import gzip, math, sys
with open(sys.argv[2], "w") as out:
    for line in gzip.open(sys.argv[1], "rt"):
        t = line.split()
        if t and t[0] == "FLASER":
            n = int(t[1]); x, y, th, stamp = float(t[n + 2]), float(t[n + 3]), float(t[n + 4]), t[n + 8]
            out.write(f"{stamp} {x} {y} 0 0 0 {math.sin(th / 2)} {math.cos(th / 2)}\n")
PY
for threads in 1 2; do
  printf 'robot: {radius: 0.25}\nmcl: {threads: %s}\n' $threads >"$tmp/carmen$threads.yaml"
done
run() {  # config, tag
  "$polyloc" localize --input "$aces" --config "$1" --map "$tmp/map.obj" --ground-truth "$tmp/truth.tum" \
    --out "$tmp/$2.tum" --csv "$tmp/$2.csv" --json >"$tmp/$2.json" 2>"$tmp/$2.err" || { cat "$tmp/$2.err" >&2; exit 1; }
}
run "$tmp/carmen1.yaml" t1
run "$tmp/carmen2.yaml" t2
run "$tmp/carmen2.yaml" t2b
cmp "$tmp/t1.tum" "$tmp/t2.tum"
cmp "$tmp/t1.csv" "$tmp/t2.csv"
cmp "$tmp/t2.tum" "$tmp/t2b.tum"
grep -q "rig from the recording: sensor 'front_laser' on /front_laser: 180 beams, -90.00..89.00 deg" "$tmp/t1.err"
grep -q "/odom: 440 of 7814 stamps do not increase (440 zero" "$tmp/t1.err"
python3 - "$tmp/t1.json" "$tmp/t1.csv" <<'PY'
import csv, json, sys
j = json.load(open(sys.argv[1]))
assert j["init"] == "ground_truth", j["init"]
c = j["counters"]
assert c["relocalizations"] == 0 and c["scans_wrong_geometry"] == 0 and c["stamps_not_increasing"] == 440, c
# Every scan of the log (the mapped even ones too) against the corrected poses: centimetres.
assert j["ate_rmse_m"] < 0.08 and j["max_pos_err_m"] < 0.4, (j["ate_rmse_m"], j["max_pos_err_m"])
assert 0 <= j["converged_after_s"] < 5, j["converged_after_s"]
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) > 400 and min(float(r["t_s"]) for r in rows) >= 0, len(rows)
PY

# A rig of a centred 179 deg scanner is not the log's -90..+89 deg: every scan is rejected with
# both geometries named; `preset: recorded` takes the log's.
cat >"$tmp/centred.yaml" <<'YAML'
robot: {radius: 0.25}
rig:
  name: centred
  sensors:
    - {name: front_laser, preset: sick_lms200, mount: {x: 0, y: 0, z: 0.3, roll: 0, pitch: 0, yaw: 0}, spec: {fov: 179, resolution: 1, range_max: 80}}
YAML
# With no scan used localize is an error (exit 1), after its counts.
rc=0; "$polyloc" localize --input "$aces" --config "$tmp/centred.yaml" --map "$tmp/map.obj" --json >"$tmp/c.json" 2>"$tmp/c.err" || rc=$?
[ "$rc" = 1 ] || { echo "localize with every scan rejected exited $rc, not 1" >&2; cat "$tmp/c.err" >&2; exit 1; }
grep -q "/front_laser: 180 beams, -90.00..89.00 deg, step 1.000 deg recorded, sensor 'front_laser' has 180 beams, -89.50..89.50 deg" "$tmp/c.err"
python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["counters"]; assert c["scans_wrong_geometry"] == 440 and c["scans_rejected"] == 440, c' "$tmp/c.json"
sed -i 's/preset: sick_lms200/preset: recorded/; s/, spec: {fov: 179, resolution: 1, range_max: 80}//' "$tmp/centred.yaml"
"$polyloc" localize --input "$aces" --config "$tmp/centred.yaml" --map "$tmp/map.obj" --json >"$tmp/r.json" 2>"$tmp/r.err"
grep -q "sensor 'front_laser' takes its geometry from /front_laser: 180 beams, -90.00..89.00 deg" "$tmp/r.err"
python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["counters"]; assert c["scans_wrong_geometry"] == 0 and c["scans"] == 440, c' "$tmp/r.json"
echo "carmen real-log user path: ok"
