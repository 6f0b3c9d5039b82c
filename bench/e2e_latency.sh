#!/usr/bin/env bash
# End-to-end latency of polylocd (not in `make test`): the lab tour simulated live and played at
# real time into polylocd, MCL with 2000 particles x 100 beams per scan, started at the tour's
# first pose. Prints play's summary: latency from a scan's publish to the pose it ended
# (p50, p99, max), frames dropped and rejected, accuracy against the ground truth.
#   bench/e2e_latency.sh [BUILD_DIR] [DURATION_S] [OUT_DIR]
set -euo pipefail
build=${1:-build}
duration=${2:-140}
out=${3:-$build/e2e}
mkdir -p "$out"
src=$(pwd)
instance=e2e_$$
# lab.yaml with 100 beams per scan (paths made absolute: the copy lives elsewhere).
sed -e "s|beams_per_scan: [0-9]*|beams_per_scan: 100|" -e "s|: \.\./|: $src/maps/|" maps/config/lab.yaml >"$out/lab_e2e.yaml"
"$build/bin/polylocd" --config "$out/lab_e2e.yaml" --instance "$instance" --control-port 0 --init 1.3,1.75,0 \
  2>"$out/polylocd.log" &
pid=$!
trap 'kill -INT $pid 2>/dev/null || true; wait $pid 2>/dev/null || true; rm -f /dev/shm/polyloc.$instance' EXIT
"$build/bin/polyloc" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --duration "$duration" --json \
  --plot "$out/e2e.png" >"$out/play.json"
/usr/bin/python3 - "$out/play.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
l, a = j["latency_ms"], j.get("accuracy", {})
print(f"poses {j['poses']}  latency p50 {l['p50']:.2f} ms  p99 {l['p99']:.2f} ms  max {l['max']:.2f} ms  "
      f"dropped {j['dropped']}  rejected {j['rejected']}  sent {j['sent']}  "
      f"ATE {a.get('ate_rmse_m', float('nan')):.4f} m  p95 {a.get('p95_pos_err_m', float('nan')):.4f} m")
PY
