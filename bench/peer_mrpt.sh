#!/usr/bin/env bash
# Peer comparison: MRPT's particle-filter localisation (pf-localization, Debian's mrpt-apps 2.5.8:
# likelihood field, 3,000 particles, its shipped config otherwise) on exactly the case that
# `polyloc eval carmen` localises (the same map grid, drift odometry, scans, start and truth),
# both scored on the same frames. Prints one JSON line. Not part of `make test`.
#   [KEEP=DIR] [MRPT_SET="SECTION.KEY=VALUE ..."] [PYTHON=/usr/bin/python3] \
#   bench/peer_mrpt.sh [BUILD_DIR] LOG STYLE DRIFT DECIMATE [TEST_SCANS]
# e.g. bench/peer_mrpt.sh build aces endpoint mid 1
# LOG names ../shared/data/carmen/LOG-corrected.log.gz; TEST_SCANS 0 (default): all.
set -euo pipefail
if ! command -v pf-localization >/dev/null; then
  echo "skipped: mrpt-apps not installed (apt-get install mrpt-apps)"
  exit 0
fi
src=$(cd "$(dirname "$0")/.." && pwd)
build=$src/build
if [ $# -ge 6 ] || { [ $# -eq 5 ] && [ -d "$1" ]; }; then build=$(cd "$1" && pwd); shift; fi
[ $# -ge 4 ] || { sed -n '2,9p' "$0" >&2; exit 2; }
log=$1 style=$2 drift=$3 dec=$4 scans=${5:-0}
python=${PYTHON:-/usr/bin/python3}
logfile="$src/../shared/data/carmen/$log-corrected.log.gz"
[ -f "$logfile" ] || { echo "missing $logfile" >&2; exit 1; }
tmp=${KEEP:-$(mktemp -d)}
mkdir -p "$tmp"
[ -n "${KEEP:-}" ] || trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}"

# The case as eval carmen localises it (--no-floor: the floor aligns each test scan on its own and
# does not change the run; --no-own: only the drift odometry is compared).
t0=$(date +%s%N)
"$build/bin/polyloc" eval carmen --log "$logfile" --map-styles "$style" --drift "$drift" --decimate "$dec" \
  --no-own --global-trials 0 --no-floor --test-scans "$scans" --save "$tmp/case" --json >"$tmp/polyloc.json" 2>"$tmp/polyloc.err" ||
  { cat "$tmp/polyloc.err" >&2; exit 1; }
t1=$(date +%s%N)
# shellcheck disable=SC2086
"$python" "$src/bench/peer_mrpt.py" convert "$tmp/case" "$style" "$drift" "$dec" "$tmp/mrpt" ${MRPT_SET:-} 2>"$tmp/convert.err" ||
  { cat "$tmp/convert.err" >&2; exit 1; }
# carmen2rawlog: CARMEN -> observation-only rawlog (odometry + scan per line);
# ros-map-yaml2mrpt: map_server YAML/PGM -> map.gridmap.gz beside it.
carmen2rawlog -q -w -i "$tmp/mrpt/run.log" -o "$tmp/mrpt/run.rawlog" >"$tmp/mrpt/carmen2rawlog.out"
ros-map-yaml2mrpt -q -w -i "$tmp/mrpt/map.yaml" -d "$tmp/mrpt" >"$tmp/mrpt/yaml2mrpt.out"
[ -f "$tmp/mrpt/map.gridmap.gz" ] || { echo "ros-map-yaml2mrpt wrote no map.gridmap.gz" >&2; exit 1; }
# stdin from /dev/null: on an error the app waits for a key (mrpt::system::pause()).
t2=$(date +%s%N)
pf-localization "$tmp/mrpt/pf.ini" </dev/null >"$tmp/mrpt/pf.out" 2>&1 || { tail -20 "$tmp/mrpt/pf.out" >&2; exit 1; }
t3=$(date +%s%N)
"$python" "$src/bench/peer_mrpt.py" score "$tmp/case" "$style" "$drift" "$dec" "$tmp/mrpt" "$tmp/mrpt/pf.out" |
  "$python" -c 'import json,sys; j=json.loads(sys.stdin.read()); j={"log": sys.argv[1], **j, "polyloc_eval_s": round(float(sys.argv[2]), 2),
    "mrpt_s": round(float(sys.argv[3]), 2), **({"files": sys.argv[4]} if sys.argv[4] else {})}; print(json.dumps(j))' \
    "$log" "$(((t1 - t0) / 1000000))e-3" "$(((t3 - t2) / 1000000))e-3" "${KEEP:-}"
