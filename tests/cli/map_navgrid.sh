#!/usr/bin/env bash
# polyloc map navgrid: the lab's free space for the lab robot (1.2 m, clearance 0.06 from
# maps/config/lab.yaml) as a map_server grid: files written and readable (PGM headers, YAML keys,
# polyloc's own grid loader via map extrude), door centres free, stairwell occupied and danger,
# a lower robot sees fewer obstacles; errors for bad options and for overwriting the inputs.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cfg="$src/maps/config/lab.yaml"

out=$("$polyloc" map navgrid --config "$cfg" --out "$tmp/nav/lab.yaml" --json)
echo "$out"
for f in lab.yaml lab.pgm lab.danger.yaml lab.danger.pgm lab.png; do [ -s "$tmp/nav/$f" ]; done
python3 - "$out" "$tmp/nav" <<'PY'
import json, os, sys
r = json.loads(sys.argv[1])
d = sys.argv[2]
assert r["height_m"] == 1.2 and r["clearance_m"] == 0.06 and r["resolution_m"] == 0.05, r
assert r["map"].endswith("lab.obj") and r["open_columns"] == 0, r
w, h = r["cells_x"], r["cells_y"]
assert r["cells_occupied"] + r["cells_free"] + r["cells_unknown"] == w * h, r
assert r["cells_free"] > 100000 and r["cells_occupied"] > 20000 and 3800 < r["cells_danger"] < 10000, r
assert sorted(os.path.basename(f) for f in r["files"]) == ["lab.danger.pgm", "lab.danger.yaml", "lab.pgm", "lab.png", "lab.yaml"], r

def pgm(path):
    data = open(path, "rb").read()
    magic, size, maxval, pixels = data.split(b"\n", 3)
    pw, ph = map(int, size.split())
    assert magic == b"P5" and maxval == b"255" and len(pixels) == pw * ph, (path, magic, size, maxval, len(pixels))
    return pw, ph, pixels

def yaml(path):
    kv = dict(line.split(": ", 1) for line in open(path).read().splitlines() if line)
    assert set(kv) == {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"}, kv
    return kv

grid, danger = yaml(d + "/lab.yaml"), yaml(d + "/lab.danger.yaml")
assert grid["image"] == "lab.pgm" and danger["image"] == "lab.danger.pgm", (grid, danger)
assert float(grid["resolution"]) == 0.05 and grid["origin"] == danger["origin"], (grid, danger)
ox, oy, _ = (float(v) for v in grid["origin"].strip("[]").split(","))
gw, gh, g = pgm(d + "/lab.pgm")
dw, dh, m = pgm(d + "/lab.danger.pgm")
assert (gw, gh) == (w, h) == (dw, dh), (gw, gh, dw, dh, w, h)
assert set(g) <= {0, 205, 254} and set(m) == {0, 254}, (set(g), set(m))
count = lambda px, v: sum(1 for p in px if p == v)
assert count(g, 0) == r["cells_occupied"] and count(g, 254) == r["cells_free"] and count(m, 0) == r["cells_danger"], r

def at(px, x, y):  # image row 0 is the top (largest y)
    i, j = int((x - ox) / 0.05), int((y - oy) / 0.05)
    return px[(h - 1 - j) * w + i]

for x in (5.0, 8.0, 17.5):  # lab doors on the corridor wall y = 3.5, 0.75 m wide
    for dx in (-0.03, 0.03):
        for y in (3.3, 3.4, 3.5, 3.6, 3.7):
            assert at(g, x + dx, y) == 254, ("door", x + dx, y, at(g, x + dx, y))
    assert at(g, x - 0.6, 3.5) == 0 and at(g, x + 0.6, 3.5) == 0, ("wall beside the door", x)
assert at(g, 24.75, 6.8) == 0 and at(m, 24.75, 6.8) == 0, "stairwell: occupied and danger"
assert at(g, 10.0, 1.5) == 254 and at(m, 10.0, 1.5) == 254, "corridor: free, no danger"
assert at(g, 21.6, 8.0) == 254, "the ramp's middle"
PY
# The preview: free white, occupied black, unknown grey, danger red.
python3 "$src/tests/tools/png_check.py" "$tmp/nav/lab.png" --min-size 1000x500 \
  --colour free=FFFFFF:10:100000 --colour occupied=000000:40:50000 --colour unknown=D7D7D7:10:10000 \
  --colour danger=DC1E1E:40:20000
# polyloc's own map_server reader takes it: the same occupied cells, extruded.
again=$("$polyloc" map extrude --grid "$tmp/nav/lab.yaml" --out "$tmp/lab_walls.obj" --json)
python3 -c 'import json,sys; a=json.loads(sys.argv[1]); b=json.loads(sys.argv[2]); assert a["cells_occupied"]==b["occupied_cells"] and b["cells_x"]==a["cells_x"], (a,b)' "$out" "$again"

# One line without --json; a robot of 0.6 m passes under the table tops (0.75 m).
line=$("$polyloc" map navgrid --config "$cfg" --robot-height 0.6 --no-preview --out "$tmp/low.yaml")
echo "$line"
grep -Eq 'lab.obj: 556 x 316 cells at 0.05 m, band 0.06..0.6 m above the floor: [0-9]+ occupied' <<<"$line"
[ ! -e "$tmp/low.png" ] && [ -s "$tmp/low.pgm" ] && [ -s "$tmp/low.danger.pgm" ]
low=$("$polyloc" map navgrid --config "$cfg" --robot-height 0.6 --no-preview --out "$tmp/low.yaml" --json)
python3 -c 'import json,sys; a=json.loads(sys.argv[1]); b=json.loads(sys.argv[2]); assert b["cells_occupied"] < a["cells_occupied"] - 1000, (a["cells_occupied"], b["cells_occupied"])' "$out" "$low"
# The old names (--height was a sensor's height in bench and demo, --clearance a robot radius in
# bench bsp): still taken, with a warning on stderr, to the same cells.
old=$("$polyloc" map navgrid --config "$cfg" --height=0.6 --clearance 0.06 --no-preview --out "$tmp/old.yaml" --json 2> "$tmp/old.err")
grep -q "warning: --height is deprecated, use --robot-height" "$tmp/old.err"
grep -q "warning: --clearance is deprecated, use --floor-clearance" "$tmp/old.err"
python3 -c 'import json,sys; a=json.loads(sys.argv[1]); b=json.loads(sys.argv[2]); assert a["cells_occupied"]==b["cells_occupied"] and b["height_m"]==0.6, (a,b)' "$low" "$old"
# --map without --config: the robot's height must be given.
"$polyloc" map navgrid --map "$src/maps/lab.obj" --robot-height 1.2 --resolution 0.1 --no-preview --out "$tmp/m.yaml" >/dev/null
[ -s "$tmp/m.pgm" ]
if err=$("$polyloc" map navgrid --map "$src/maps/lab.obj" --out "$tmp/n.yaml" 2>&1); then exit 1; fi
grep -q "without --config give the robot's --robot-height" <<<"$err"

# Bad options: the message names the option and the value; nothing is written.
for bad in 0 -0.05 2 nan; do
  if err=$("$polyloc" map navgrid --config "$cfg" --resolution "$bad" --out "$tmp/bad.yaml" 2>&1); then exit 1; fi
  echo "$err"
  grep -q "resolution = $bad" <<<"$err"
done
if err=$("$polyloc" map navgrid --config "$cfg" --robot-height 0.05 --out "$tmp/bad.yaml" 2>&1); then exit 1; fi
grep -q "height = 0.05: must be a finite number > clearance (0.06 m)" <<<"$err"
if err=$("$polyloc" map navgrid --config "$cfg" --resolution abc --out "$tmp/bad.yaml" 2>&1); then exit 1; fi
grep -q -- "--resolution" <<<"$err"
[ ! -e "$tmp/bad.yaml" ] && [ ! -e "$tmp/bad.pgm" ]
if err=$("$polyloc" map navgrid --config "$cfg" --out "$tmp/grid.pgm" 2>&1); then exit 1; fi
grep -q "expected a map_server YAML" <<<"$err"
# A mesh with no floor label: the labels looked for and the labels it has.
printf 'o wall\nv 0 0 0\nv 1 0 0\nv 1 0 1\nf 1 2 3\n' >"$tmp/wall.obj"
if err=$("$polyloc" map navgrid --map "$tmp/wall.obj" --robot-height 1 --out "$tmp/w.yaml" 2>&1); then exit 1; fi
grep -q "no walkable floor: no triangle labelled floor, ramp .*its labels: wall (1)" <<<"$err"

# Never over the inputs: the map (a copy here) and the config stay as they were.
before=$(md5sum "$cfg" "$src/maps/lab.obj")
cp "$src/maps/lab.obj" "$tmp/lab.obj"
if err=$("$polyloc" map navgrid --map "$tmp/lab.obj" --robot-height 1.2 --out "$tmp/lab.obj" 2>&1); then exit 1; fi
grep -q -- "--out $tmp/lab.obj is the input --map: refusing to overwrite it" <<<"$err"
cmp "$tmp/lab.obj" "$src/maps/lab.obj"
if err=$("$polyloc" map navgrid --config "$cfg" --out "$cfg" 2>&1); then exit 1; fi
grep -q "is the input --config: refusing to overwrite it" <<<"$err"
if err=$("$polyloc" map navgrid --config "$cfg" --out "$src/maps/lab.obj" 2>&1); then exit 1; fi
grep -q "is the input map (of --config): refusing to overwrite it" <<<"$err"
[ "$(md5sum "$cfg" "$src/maps/lab.obj")" = "$before" ]
echo OK
