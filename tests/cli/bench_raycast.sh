#!/usr/bin/env bash
# polyloc bench raycast as a user runs it: one JSON object with the documented keys.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2
out=$("$polyloc" bench raycast --map "$src/maps/office.obj" --poses 200 --beams 32 --threads 2 --sensor-height 0.3 --repeat 1 --json)
echo "$out"
for key in rays_per_s mean_range_m rtcintersect1_rays_per_s ratio_vs_rtcintersect1 speedup_vs_1_thread; do
  grep -q "\"$key\":" <<<"$out" || { echo "missing key $key"; exit 1; }
done
# Same rays through both paths: no range differs.
grep -q '"range_mismatches_vs_rtcintersect1":0' <<<"$out"
# The mean range is a plausible indoor distance (misses count as 30 m).
mean=$(sed -E 's/.*"mean_range_m":([0-9.e+-]+).*/\1/' <<<"$out")
awk -v m="$mean" 'BEGIN { exit !(m > 0.5 && m < 30) }'
# A missing map is an error that names the file.
if err=$("$polyloc" bench raycast --map /nonexistent/map.obj --json 2>&1); then exit 1; fi
grep -q '/nonexistent/map.obj' <<<"$err"
echo OK
