#!/usr/bin/env bash
# What viewers cost polylocd (not in `make test`): the lab tour played at real time into
# polylocd, as bench/e2e_latency.sh, once with 0, 1 and 5 viewers attached to its live view
# (tests/js/live_viewer.mjs: every channel subscribed and read, as Foxglove with all panels).
# The viewer counts take turns, REPEATS rounds of them (the machine's noise moves a p99 of 500
# poses by 20 % from run to run; taking turns spreads it over all counts alike). Prints per count
# the median over the rounds of the scan-to-pose latency (p50, p99, max), polylocd's CPU (per cent
# of one core over the run), the frames lost in all, and what the viewers received; one JSON
# object on stdout.
#   bench/live_viewers.sh [BUILD_DIR] [DURATION_S] [OUT_DIR] [REPEATS] [VIEWERS...]
set -euo pipefail
build=${1:-build}
duration=${2:-60}
out=${3:-$build/live_viewers}
repeats=${4:-3}
shift $(( $# < 4 ? $# : 4 ))
counts=(0 1 5)
[ $# -gt 0 ] && counts=("$@")
mkdir -p "$out"
src=$(pwd)
command -v node >/dev/null || { echo "node is not on PATH (apt-get install nodejs; make deps does)" >&2; exit 1; }
[ -d tests/js/node_modules/ws ] || (cd tests/js && npm ci --no-audit --no-fund --loglevel=error) >&2
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
sed -e "s|beams_per_scan: [0-9]*|beams_per_scan: 100|" -e "s|: \.\./|: $src/maps/|" maps/config/lab.yaml >"$out/lab_live.yaml"
pid=
viewers=()
cleanup() {
  for v in "${viewers[@]}"; do kill "$v" 2>/dev/null || true; done
  [ -n "$pid" ] && { kill -INT "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; }
  rm -f /dev/shm/polyloc.live_bench_$$
}
trap cleanup EXIT
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }

for r in $(seq 1 "$repeats"); do
for n in "${counts[@]}"; do
  echo "live_viewers: round $r of $repeats: $n viewer(s), ${duration} s of the lab tour" >&2
  "$build/bin/polylocd" --config "$out/lab_live.yaml" --instance live_bench_$$ --control-port 0 --live-port "$port" \
    --init 1.3,1.75,0 2>"$out/polylocd_$n.log" &
  pid=$!
  for _ in $(seq 100); do curl -sf -o /dev/null "http://127.0.0.1:$port/" && break; sleep 0.1; done
  viewers=()
  for k in $(seq 1 "$n"); do
    node tests/js/live_viewer.mjs "ws://127.0.0.1:$port" >"$out/viewer_${n}_${r}_$k.json" &
    viewers+=($!)
  done
  sleep 1
  t0=$(cpu_ticks $pid)
  "$build/bin/polyloc" play --scenario maps/scenarios/lab_tour.yaml --shm live_bench_$$ --duration "$duration" --json \
    --quiet >"$out/play_${n}_$r.json"
  t1=$(cpu_ticks $pid)
  for v in "${viewers[@]}"; do kill -TERM "$v"; wait "$v" || true; done
  viewers=()
  kill -INT "$pid"; wait "$pid"; pid=
  echo "$(( t1 - t0 ))" >"$out/cpu_ticks_${n}_$r"
done
done

/usr/bin/python3 - "$out" "$duration" "$(getconf CLK_TCK)" "$repeats" "${counts[@]}" <<'PY'
import json, statistics, sys
out, duration, hz, repeats, counts = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), sys.argv[5:]
med = statistics.median
runs = {}
for n in counts:
    plays = [json.load(open(f"{out}/play_{n}_{r}.json")) for r in range(1, repeats + 1)]
    cpu = [100.0 * float(open(f"{out}/cpu_ticks_{n}_{r}").read()) / hz / duration for r in range(1, repeats + 1)]
    got = [json.loads(open(f"{out}/viewer_{n}_{r}_{k}.json").read() or "{}")
           for r in range(1, repeats + 1) for k in range(1, int(n) + 1)]
    lat = {q: med([p["latency_ms"][q] for p in plays]) for q in ("p50", "p99", "max")}
    runs[n] = {"latency_ms": lat, "p99_each_ms": [p["latency_ms"]["p99"] for p in plays],
               "poses": med([p["poses"] for p in plays]), "lost": sum(p["dropped"] + p["rejected"] for p in plays),
               "cpu_percent": med(cpu), "viewer_messages": med([g.get("messages", 0) for g in got]) if got else 0,
               "viewer_mib_per_s": med([g.get("bytes", 0) / 2**20 / duration for g in got]) if got else 0}
    r = runs[n]
    print(f"{n} viewer(s), median of {repeats}: latency p50 {lat['p50']:.2f} ms  p99 {lat['p99']:.2f} ms "
          f"(each {', '.join(f'{v:.1f}' for v in r['p99_each_ms'])})  max {lat['max']:.2f} ms  cpu {r['cpu_percent']:.0f}%  "
          f"lost {r['lost']}  each viewer got {r['viewer_messages']:.0f} messages, {r['viewer_mib_per_s']:.2f} MiB/s", file=sys.stderr)
res = {"duration_s": duration, "repeats": repeats, "runs": runs}
if "0" in runs:
    base = runs["0"]["latency_ms"]["p99"]
    res["p99_ratio"] = {n: runs[n]["latency_ms"]["p99"] / base for n in runs if n != "0"}
    res["cpu_ratio"] = {n: runs[n]["cpu_percent"] / runs["0"]["cpu_percent"] for n in runs if n != "0"}
print(json.dumps(res))
PY
