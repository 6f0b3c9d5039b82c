#!/usr/bin/env bash
# The real-log robustness matrix of docs/benchmarks.md: `polyloc eval carmen --matrix` (every map
# style x drift low, mid, high, slip x every scan, every 2nd, every 4th; 20 global trials per map
# style) with the defaults (no config) on every shared log (../shared/data/carmen), and the log's
# own odometry. Writes OUT/<log>.json, OUT/<log>.png (map, paths, global starts) and
# OUT/<log>_strips.png (error over time, one strip per case); prints the markdown tables (per log
# and map style; per drift and decimation) and writes OUT/figures.json. With CHECK=FILE compares
# with the claimed figures in FILE (docs/carmen_figures.json): exit 1 when one regressed by 1.5x
# (ATE, ratio to the floor, tracking frames beyond 0.5 m, unannounced jumps, global failures).
# About 90 minutes on 2 cores; LOGS="aces csail" and ARGS="--map-styles polyloc --drift mid
# --decimate 1" run less.
#   [CHECK=docs/carmen_figures.json] [LOGS=...] [ARGS=...] bench/carmen_table.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
build=${1:-build}
out=${2:-$build/carmen_table}
data=../shared/data/carmen
[ -d "$data" ] || { echo "missing $data (the shared real logs; run from the repository root)" >&2; exit 1; }
mkdir -p "$out"
logs=${LOGS:-aces csail edmonton freiburg-079 freiburg-101 infinite-corridor orebro seattle}
args=${ARGS:---matrix}
for log in $logs; do
  echo "eval carmen $log ..." >&2
  # shellcheck disable=SC2086
  "$build/bin/polyloc" eval carmen --log "$data/$log-corrected.log.gz" $args --json --plot "$out/$log.png" \
    --strips "$out/${log}_strips.png" >"$out/$log.json" 2>"$out/$log.err"
done
python3 "$(dirname "$0")/carmen_table.py" "$out" "${CHECK:-}" $logs
