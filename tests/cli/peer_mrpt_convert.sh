#!/usr/bin/env bash
# bench/peer_mrpt.py's converter (eval carmen --save -> MRPT's inputs) without MRPT: on the first
# 40 test scans of aces, the CARMEN log has one ROBOTLASER1 line per scan with the MCAP's beams,
# ranges, stamps and drift odometry (/odom at the scan, not the truth), the laser pose turned by the
# scan's middle angle; the map YAML points at the same PGM with a whole-cell origin; the
# pf-localization config has 3,000 fixed particles, a start box around the first truth pose and
# the shipped config's sections. Usage: peer_mrpt_convert.sh POLYLOC SRC
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
pydir="$(dirname "$polyloc")/../python"
[ -d "$pydir/polyloc" ] || { echo "skipped: no Python module in $pydir (POLYLOC_BUILD_PYTHON=OFF?)"; exit 0; }
log="$src/../shared/data/carmen/aces-corrected.log.gz"
[ -f "$log" ] || { echo "missing $log (the shared real logs)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$polyloc" eval carmen --log "$log" --map-styles endpoint --drift mid --decimate 1 --no-own --global-trials 0 \
  --no-floor --test-scans 40 --save "$tmp/case" --json >/dev/null 2>"$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
# The shipped config is read when MRPT is installed; else a stand-in with its sections.
ini=/usr/share/mrpt/config_files/pf-localization/localization_demo_obsonly_rawlog.ini
export PYTHONPATH="$pydir"
/usr/bin/python3 - "$src/bench/peer_mrpt.py" "$tmp" "$ini" <<'PY'
import importlib.util, math, os, sys
script, tmp, ini = sys.argv[1:4]
spec = importlib.util.spec_from_file_location("peer_mrpt", script)
pm = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pm)
if not os.path.exists(ini):
    pm.SHIPPED_INI = f"{tmp}/stand_in.ini"
    open(pm.SHIPPED_INI, "w").write("[PF_options]\nadaptiveSampleSize=1\n[LocalizationExperiment]\nparticles_count=40000\n"
                                    "init_PDF_mode=0\n[MetricMap]\noccupancyGrid_count=1\n")
out = f"{tmp}/mrpt"
pm.convert(f"{tmp}/case", "endpoint", "mid", "1", out, [])
odom_t, odom, scans, truth = pm.read_case(f"{tmp}/case/endpoint_mid_x1.mcap")
assert len(scans) == 40 and len(truth) == 40, (len(scans), len(truth))

lines = [l.split() for l in open(f"{out}/run.log") if not l.startswith("#")]
assert len(lines) == 40 and all(l[0] == "ROBOTLASER1" for l in lines), len(lines)
for l, m in zip(lines, scans):
    n = int(l[8])
    assert n == len(m["ranges"]) == 180 and len(l) == 9 + n + 1 + 6 + 5 + 3, (n, len(l))
    fov, inc = float(l[3]), float(l[4])
    assert abs(fov - inc * (n - 1)) < 1e-6 and abs(float(l[2]) + fov / 2) < 1e-6
    for got, want in zip(l[9:9 + n], m["ranges"]):
        if math.isfinite(want) and m["range_min"] <= want < m["range_max"]:
            assert abs(float(got) - want) < 6e-4, (got, want)
        else:
            assert float(got) in (0.0, m["range_max"]), (got, want)
    assert l[9 + n] == "0"  # no remissions
    lx, ly, lth, rx, ry, rth = map(float, l[10 + n:16 + n])
    ox, oy, oth = pm.odom_at(odom_t, odom, m["stamp_ns"])
    assert max(abs(rx - ox), abs(ry - oy), abs(rth - oth)) < 1e-6, "robot pose is not the drift odometry"
    assert (lx, ly) == (rx, ry) and abs(lth - rth - (m["angle_min"] + fov / 2)) < 1e-6, "laser pose"
    assert l[-3] == l[-1] == pm.carmen_stamp(m["stamp_ns"]), l[-3:]
# /odom at each scan is the drift odometry, not the truth (another frame, drifting).
assert any(abs(float(l[-11]) - t[0]) > 0.05 for l, t in zip(lines, (truth[m["stamp_ns"]] for m in scans)))

y = dict(l.split(":", 1) for l in open(f"{out}/map.yaml"))
res, origin = float(y["resolution"]), [float(v) for v in y["origin"].strip(" []\n").split(",")]
assert all(abs(o / res - round(o / res)) < 1e-6 for o in origin[:2]), origin
assert open(f"{out}/map.pgm", "rb").read() == open(f"{tmp}/case/endpoint/map.pgm", "rb").read()

sec, keys = None, {}
for l in open(f"{out}/pf.ini"):
    s = l.split("//")[0].strip()
    if s.startswith(("#", ";")):
        continue
    if s.startswith("["):
        sec = s.strip("[]")
    elif "=" in s:
        k, v = (p.strip() for p in s.split("=", 1))
        assert (sec, k) not in keys, f"{sec}.{k} twice"
        keys[sec, k] = v
L = "LocalizationExperiment"
assert keys[L, "particles_count"] == "3000" and keys["PF_options", "adaptiveSampleSize"] == "0"
assert keys[L, "init_PDF_mode"] == "1" and keys[L, "map_file"].endswith("map.gridmap.gz")
t0 = min(truth)
cx = (float(keys[L, "init_PDF_min_x"]) + float(keys[L, "init_PDF_max_x"])) / 2
cy = (float(keys[L, "init_PDF_min_y"]) + float(keys[L, "init_PDF_max_y"])) / 2
cw = (float(keys[L, "init_PDF_min_yaw_deg"]) + float(keys[L, "init_PDF_max_yaw_deg"])) / 2
assert abs(cx - truth[t0][0]) < 1e-6 and abs(cy - truth[t0][1]) < 1e-6 and abs(cw - math.degrees(truth[t0][2])) < 1e-6
assert abs(float(keys[L, "init_PDF_max_x"]) - cx - math.sqrt(3) * 0.1) < 1e-6
print(f"peer_mrpt_convert: 40 scans x 180 beams, odometry, map and config as expected")
PY
