#!/usr/bin/env bash
# What `make run` runs: map summary, ranges per scan, and a PNG.
set -euo pipefail
polyloc=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
out=$("$polyloc" demo --map maps/lab.obj --out "$tmp/demo.png" --poses 3)
echo "$out"
grep -q '^triangles' <<<"$out"
[ "$(grep -c '^== scan' <<<"$out")" = 3 ]
# PNG signature
[ "$(head -c 8 "$tmp/demo.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]
echo OK
