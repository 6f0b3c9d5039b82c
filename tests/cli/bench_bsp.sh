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
for kind in planar 3d; do
  agree=$(sed -E "s/.*\"agree_1mm_$kind\":([0-9.e+-]+).*/\1/" <<<"$out")
  awk -v a="$agree" 'BEGIN { exit !(a >= 0.999) }' || { echo "agreement $kind $agree"; exit 1; }
done
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
