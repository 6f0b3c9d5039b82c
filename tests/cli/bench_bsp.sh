#!/usr/bin/env bash
# polyloc bench bsp as a user runs it: one JSON object with both backends' figures; the BSP agrees
# with Embree on the same rays; an open map is refused with a message that names it.
set -euo pipefail
polyloc=$1 src=$2
# 0.25 m: at 0.3 m planar rays graze the top of the lab's loading platform (a tie, docs/raycast.md).
out=$("$polyloc" bench bsp --map "$src/maps/lab.obj" --rays 2000 --points 2000 --height 0.25 --repeat 1 --json)
echo "$out"
for key in build_s memory_mb nodes depth rays_per_s_planar rays_per_s_3d point_queries_per_s agree_1mm_planar; do
  grep -q "\"$key\":" <<<"$out" || { echo "missing key $key"; exit 1; }
done
grep -q '"embree":{' <<<"$out"
python3 -c 'import json, sys
b = json.loads(sys.argv[1])["bsp"]
for kind in ("planar", "3d"):
    assert b["agree_1mm_" + kind] >= 0.999, (kind, b["agree_1mm_" + kind])' "$out"
# The Bresenham rows (grid2d at 5, 4, 1 cm on the same planar rays): ranges within about a cell
# of Embree's at the median, finer grids closer, and a 1 cm grid holding more memory.
python3 - "$out" <<'PY'
import json, sys
g = json.loads(sys.argv[1])["grid2d"]
assert sorted(g) == ["0.01", "0.04", "0.05"], sorted(g)
for res, row in g.items():
    assert row["rays_per_s_planar"] > 0 and row["point_queries_per_s"] > 0, row
    assert row["range_err_median_m_planar"] <= float(res), (res, row["range_err_median_m_planar"])
    assert row["point_agree"] > 0.7, row
assert g["0.01"]["range_err_median_m_planar"] < g["0.05"]["range_err_median_m_planar"]
assert g["0.01"]["memory_mb"] > 10 * g["0.05"]["memory_mb"]
PY
# The thesis-sized model: the lab's walls, floor, doors, glass, ramp, tables and cabinets.
small=$("$polyloc" bench bsp --map "$src/maps/lab.obj" --labels wall,floor,door,glass,ramp,table,cabinet \
  --rays 500 --points 500 --repeat 1 --json)
grep -q '"triangles":2056' <<<"$small"
# An open map: the error names the file and says what bsp needs.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n' >"$tmp/open.obj"
if err=$("$polyloc" bench bsp --map "$tmp/open.obj" --rays 10 --json 2>&1); then exit 1; fi
echo "$err"
grep -q "open.obj: 3 open edges, e.g. at" <<<"$err"
grep -q "bsp needs closed, outward-facing solids" <<<"$err"
echo OK
