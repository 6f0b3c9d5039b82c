#!/usr/bin/env bash
# polyloc map extrude: a small map_server grid (PGM + YAML written here) to a closed OBJ that
# `polyloc map info` accepts; errors name the file and key. Then --carmen: a corrected CARMEN log
# of a 4 x 3 m room (FLASER lines with known laser poses, written here) to a grid and an OBJ.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# 20 x 10 cells: a black frame (occupied) around white (free).
python3 - "$tmp/g.pgm" <<'PY'
import sys
w, h = 20, 10
px = bytes(0 if x in (0, w - 1) or y in (0, h - 1) else 254 for y in range(h) for x in range(w))
open(sys.argv[1], "wb").write(b"P5\n%d %d\n255\n" % (w, h) + px)
PY
printf 'image: g.pgm\nresolution: 0.1\norigin: [-1.0, -0.5, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n' >"$tmp/g.yaml"
out=$("$polyloc" map extrude --grid "$tmp/g.yaml" --wall-height 2.0 --out "$tmp/g.obj" --resolution-merge --json)
echo "$out"
grep -q '"closed":true' <<<"$out"
grep -q '"occupied_cells":56' <<<"$out"
info=$("$polyloc" map info "$tmp/g.obj" --json)
grep -q '"closed":true' <<<"$info"
grep -q '"consistent_winding":true' <<<"$info"
printf 'image: g.pgm\nresolution: 0\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n' >"$tmp/bad.yaml"
if err=$("$polyloc" map extrude --grid "$tmp/bad.yaml" --out "$tmp/b.obj" 2>&1); then exit 1; fi
grep -q 'bad.yaml' <<<"$err"
grep -q 'resolution' <<<"$err"

# A corrected CARMEN log: 24 FLASER scans of a 4 x 3 m room from known laser poses, ODOM lines,
# one scan with no reading (skipped), one broken line (a reader warning).
python3 - "$tmp/room.log" <<'PY'
import math, sys
x0, y0, x1, y1 = -1.98, -1.47, 2.02, 1.53
def ray(px, py, a):
    dx, dy = math.cos(a), math.sin(a)
    tx = (x1 - px) / dx if dx > 1e-12 else (x0 - px) / dx if dx < -1e-12 else math.inf
    ty = (y1 - py) / dy if dy > 1e-12 else (y0 - py) / dy if dy < -1e-12 else math.inf
    return min(tx, ty)
with open(sys.argv[1], "w") as f:
    f.write("PARAM laser_front_laser_resolution 0.5 0 host 0\nPARAM robot_front_laser_max 50.0 0 host 0\n")
    for i in range(24):
        a = 2 * math.pi * i / 12
        x, y = 0.02 + 1.2 * math.cos(a), 0.03 + 0.8 * math.sin(a)
        th = a + math.pi / 2 + (math.pi if i >= 12 else 0)
        t = "%.1f host 0\n" % (100 + 0.1 * i)
        f.write("ODOM %.4f %.4f %.4f 0 0 0 " % (x + 0.1, y, th) + t)
        r = " ".join("%.4f" % ray(x, y, th - math.pi / 2 + k * math.pi / 360) for k in range(361))
        f.write("FLASER 361 %s %.6f %.6f %.6f %.4f %.4f %.4f " % (r, x, y, th, x + 0.1, y, th) + t)
    f.write("FLASER 2 0 0 0 0 0 0 0 0 200.0 host 0\n")
    f.write("FLASER 2 1 1 0 0 oops 0 0 0 200.1 host 0\n")
PY
out=$("$polyloc" map extrude --carmen "$tmp/room.log" --out "$tmp/room.obj" --save-grid "$tmp/room_grid.yaml" \
  --plot "$tmp/room.png" --json 2>"$tmp/err")
# The plot (cmd_map_extrude.cpp): the grid (occupied black), the extruded walls' slice red, the
# laser path blue: 1,158 red and 787 blue pixels here, half of each required.
python3 "$(dirname "$0")/../tools/png_check.py" "$tmp/room.png" --min-size 200x150 --min-colours 50 --ink 0.05,0.5 \
  --colour walls=DC1E1E:40:580 --colour path=285ADC:40:390
echo "$out"
python3 - "$out" "$tmp/room.log" <<'PY'
import json, sys
r = json.loads(sys.argv[1])
assert r["carmen"] == sys.argv[2] and r["closed"] and r["consistent_winding"], r
assert r["scans_used"] == 24 and r["scans_skipped"] == 1, r
assert r["skipped_reasons"] == {"no_valid_ranges": 1}, r
assert r["rejected_lines"] == 1 and r["resolution_m"] == 0.05, r
# 4 x 3 m of walls at 5 cm: about 280 cells of outline; the grid is the room and its padding.
assert 250 <= r["occupied_cells"] <= 700, r
assert 84 <= r["cells_x"] <= 90 and 64 <= r["cells_y"] <= 70, r
PY
grep -q "room.log:.*FLASER: field .* is not a number: 'oops'" "$tmp/err"
[ -f "$tmp/room_grid.yaml" ] && [ -f "$tmp/room_grid.pgm" ]
# The saved grid extrudes to the same map.
again=$("$polyloc" map extrude --grid "$tmp/room_grid.yaml" --out "$tmp/again.obj" --json)
python3 -c 'import json,sys; a=json.loads(sys.argv[1]); b=json.loads(sys.argv[2]); assert a["occupied_cells"]==b["occupied_cells"] and a["triangles"]==b["triangles"], (a,b)' "$out" "$again"
info=$("$polyloc" map info "$tmp/room.obj" --json)
grep -q '"closed":true' <<<"$info"
# --laser rear: there is none; a log with no laser lines; neither or both sources.
if err=$("$polyloc" map extrude --carmen "$tmp/room.log" --laser rear --out "$tmp/r.obj" 2>&1); then exit 1; fi
grep -q "room.log: no usable laser scan with a pose on /rear_laser" <<<"$err"
printf 'ODOM 1 2 3 0 0 0 5.0 host 5.0\n' >"$tmp/odom.log"
if err=$("$polyloc" map extrude --carmen "$tmp/odom.log" --out "$tmp/o.obj" 2>&1); then exit 1; fi
grep -q "odom.log: no usable laser scan" <<<"$err"
[ ! -e "$tmp/o.obj" ]
if err=$("$polyloc" map extrude --out "$tmp/n.obj" 2>&1); then exit 1; fi
grep -q "exactly one of --grid and --carmen" <<<"$err"
if err=$("$polyloc" map extrude --grid "$tmp/g.yaml" --carmen "$tmp/room.log" --out "$tmp/n.obj" 2>&1); then exit 1; fi
grep -q "excludes" <<<"$err"
if err=$("$polyloc" map extrude --grid "$tmp/g.yaml" --resolution 0.1 --out "$tmp/n.obj" 2>&1); then exit 1; fi
grep -q "only with --carmen" <<<"$err"
echo OK
