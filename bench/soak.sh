#!/usr/bin/env bash
# Soak test of polylocd (not in `make test`): a closed loop of the office with the taser rig, whose two
# SICK LMS200 scan at 75 Hz, simulated live and played at real time in a loop for DURATION
# seconds (default 600). Samples polylocd's resident memory every 10 s into OUT/rss.csv and
# prints the play summary and the memory figures: first (after the first minute), last, max.
#   bench/soak.sh [BUILD_DIR] [DURATION_S] [OUT_DIR]
set -euo pipefail
build=${1:-build}
duration=${2:-600}
out=${3:-$build/soak}
mkdir -p "$out"
instance=soak_$$
"$build/bin/polylocd" --config maps/config/office.yaml --instance "$instance" --init 1.0,1.5,90 --log-level warn 2>"$out/polylocd.log" &
pid=$!
trap 'kill -INT $pid 2>/dev/null || true; wait $pid 2>/dev/null || true; rm -f /dev/shm/polyloc.$instance' EXIT
echo "t_s,rss_kib" >"$out/rss.csv"
(
  t=0
  while kill -0 $pid 2>/dev/null; do
    rss=$(awk '/VmRSS/ {print $2}' /proc/$pid/status 2>/dev/null || echo "")
    [ -n "$rss" ] && echo "$t,$rss" >>"$out/rss.csv"
    sleep 10
    t=$((t + 10))
  done
) &
sampler=$!
"$build/bin/polyloc" play --scenario maps/scenarios/office_loop.yaml --shm "$instance" --loop \
  --duration "$duration" --json --plot "$out/soak.png" >"$out/play.json"
kill $sampler 2>/dev/null || true
cat "$out/play.json"
awk -F, 'NR > 1 && $1 >= 60 { if (!first) first = $2; last = $2; if ($2 > max) max = $2 }
  END { printf "polylocd RSS: %.1f MiB after 60 s, %.1f MiB at the end, %.1f MiB max (%s/rss.csv)\n", first / 1024, last / 1024, max / 1024, "'"$out"'" }' "$out/rss.csv"
