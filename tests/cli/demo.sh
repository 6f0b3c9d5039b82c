#!/usr/bin/env bash
# What `make run` runs: map summary, ranges per scan, and a PNG with the rays drawn (png_check).
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
out=$("$polyloc" demo --map maps/lab.obj --out "$tmp/demo.png" --poses 3)
echo "$out"
grep -q '^triangles' <<<"$out"
[ "$(grep -c '^== scan' <<<"$out")" = 3 ]
# The picture (cmd_demo.cpp): the lab's slices, then every 4th beam of scan 1, 2, 3 as red, blue,
# green lines. Measured: 14,739 red (253 of them the map's danger-labelled marks), 15,928 blue,
# 10,718 green pixels; half of each scan's is required (a blank or ray-less picture fails).
python3 tests/tools/png_check.py "$tmp/demo.png" --size 1132x652 --min-colours 1000 --ink 0.1,0.5 \
  --colour scan1=DC1E1E:40:7500 --colour scan2=285ADC:40:8000 --colour scan3=1EA03C:40:5000
echo OK
