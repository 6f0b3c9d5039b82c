#!/usr/bin/env bash
# polyloc map extrude: a small map_server grid (PGM + YAML written here) to a closed OBJ that
# `polyloc map info` accepts; errors name the file and key.
set -euo pipefail
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
out=$("$polyloc" map extrude --grid "$tmp/g.yaml" --height 2.0 --out "$tmp/g.obj" --resolution-merge --json)
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
echo OK
