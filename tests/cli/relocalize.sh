#!/usr/bin/env bash
# polyloc relocalize on one machine, as a user types it: two 20 s lab tours (two seeds) and one
# unreadable input with --jobs 1: the bad input is reported, the others finish, the exit status
# is 1; the same two with --jobs 2: exit 0 and the same trajectories bit for bit (counter-based
# random numbers); every output (TUM, CSV with covariance and ESS, PNG, JSON summaries).
set -euo pipefail
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
"$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 20 --out "$tmp/a.mcap" >/dev/null
"$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 20 --seed 2 --out "$tmp/b.mcap" >/dev/null
echo "not a recording" > "$tmp/bad.mcap"
set +e
"$polyloc" relocalize --config maps/config/lab.yaml --input "$tmp/a.mcap" "$tmp/bad.mcap" "$tmp/b.mcap" \
  --out "$tmp/j1" --jobs 1 >"$tmp/out1" 2>"$tmp/err1"
rc=$?
set -e
cat "$tmp/out1"
[ $rc -eq 1 ] || { echo "expected exit 1 with a bad input, got $rc" >&2; cat "$tmp/err1" >&2; exit 1; }
grep -q "bad.mcap" "$tmp/err1"
"$polyloc" relocalize --config maps/config/lab.yaml --input "$tmp/a.mcap" "$tmp/b.mcap" --out "$tmp/j2" --jobs 2 \
  --covariance full --json >"$tmp/out2"
python3 - "$tmp" <<'PY'
import json, os, sys
tmp = sys.argv[1]
s1 = json.load(open(f"{tmp}/j1/summary.json"))
assert s1["all_succeeded"] is False and s1["succeeded"] == 2 and s1["failed"] == 1, s1
bad = [i for i in s1["inputs"] if i["name"] == "bad"][0]
assert bad["status"] == "failed" and bad["errors"] and "bad.mcap" in bad["errors"][0]["error"], bad
assert [m["input"].endswith("bad.mcap") for m in s1["missing"]] == [True], s1["missing"]
s2 = json.loads(open(f"{tmp}/out2").read())
assert s2["all_succeeded"] is True and s2["jobs"] == 2, s2
assert s2["accuracy"]["frames"] > 20 and s2["accuracy"]["ate_rmse_m"] < 0.005, s2["accuracy"]  # lab_tour: 0.33 cm claimed (x1.5)
for name in ("a", "b"):
    t1 = open(f"{tmp}/j1/{name}/trajectory.tum").read()
    t2 = open(f"{tmp}/j2/{name}/trajectory.tum").read()
    assert t1 == t2 and t1.count("\n") > 20, f"{name}: --jobs 1 and --jobs 2 differ"
    j = json.load(open(f"{tmp}/j2/{name}/summary.json"))
    assert j["status"] == "ok" and j["init"] == "ground_truth" and j["ate_rmse_m"] < 0.005, j
    assert j["frames"] == t2.count("\n") - sum(l.startswith("#") for l in t2.splitlines()), j["frames"]
    csv = open(f"{tmp}/j2/{name}/frames.csv").read().splitlines()
    assert "pos_err_m" in csv[0] and "cov_55" in csv[0] and csv[0].endswith(",ess,particles,seen_through,refined,map_fit"), csv[0]
    assert len(csv) == 1 + j["evaluated_frames"], (len(csv), j["evaluated_frames"])
    c1 = open(f"{tmp}/j1/{name}/frames.csv").readline()
    assert "var_yaw" in c1 and "cov_00" not in c1, c1
    assert open(f"{tmp}/j2/{name}/plot.png", "rb").read(8) == b"\x89PNG\r\n\x1a\n"
PY
