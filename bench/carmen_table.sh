#!/usr/bin/env bash
# The real-log table of docs/benchmarks.md: `polyloc eval carmen` with the defaults (no config)
# on every shared log (../shared/data/carmen), the full protocol (every odd scan, 20 global
# trials). Writes OUT/<log>.json and OUT/<log>.png, prints the markdown table, and with
# CHECK=FILE compares each figure with the claimed ones in FILE (docs/carmen_figures.json):
# exit 1 when one regressed by 1.5x (ATE, p95, worst frame, ratio to the floor; global
# failures; a relocalisation where there was none). About 9 minutes on 2 cores.
#   [CHECK=docs/carmen_figures.json] bench/carmen_table.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
build=${1:-build}
out=${2:-$build/carmen_table}
data=../shared/data/carmen
[ -d "$data" ] || { echo "missing $data (the shared real logs; run from the repository root)" >&2; exit 1; }
mkdir -p "$out"
logs="aces csail edmonton freiburg-079 freiburg-101 infinite-corridor orebro seattle"
for log in $logs; do
  echo "eval carmen $log ..." >&2
  "$build/bin/polyloc" eval carmen --log "$data/$log-corrected.log.gz" --json --plot "$out/$log.png" \
    >"$out/$log.json" 2>"$out/$log.err"
done
python3 - "$out" "${CHECK:-}" $logs <<'PY'
import json, math, sys
out, check, logs = sys.argv[1], sys.argv[2], sys.argv[3:]
def cm(x): return "n/a" if x is None else f"{100 * x:.1f}"
rows, figures = [], {}
print("| log | test scans | floor RMSE / p95 | drift: ATE (x floor) / p95 / p95 yaw / worst | own: ATE (x floor) / p95 (x floor p95) / odometry alone | relocalisations | global (20) | updates/s |")
print("| --- | ---: | --- | --- | --- | ---: | ---: | ---: |")
for log in logs:
    j = json.load(open(f"{out}/{log}.json"))
    f, d, o, g = j["floor"], j["variants"]["drift"], j["variants"]["own"], j["global"]
    fig = {"floor_m": f["ate_rmse_m"], "global_succeeded": g["succeeded"], "variants": {}}
    for name, v in (("drift", d), ("own", o)):
        if "unusable" in v:
            fig["variants"][name] = {"unusable": v["unusable"]}
            continue
        fig["variants"][name] = {k: v[k] for k in ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor")}
        fig["variants"][name]["relocalizations"] = v["counters"]["relocalizations"]
        fig["variants"][name]["odometry_only_ate_m"] = v["odometry_only"]["ate_rmse_m"]
    figures[log] = fig
    own = (f"{cm(o['ate_rmse_m'])} cm ({o['ate_over_floor']:.2f}x) / {cm(o['p95_pos_err_m'])} cm ({o['p95_over_floor']:.2f}x) / "
           f"{cm(o['odometry_only']['ate_rmse_m'])} cm") if "unusable" not in o else "none of its own (its ODOM lines copy the corrected poses)"
    rel = d["counters"]["relocalizations"] + (o["counters"]["relocalizations"] if "unusable" not in o else 0)
    print(f"| {log} | {j['test_scans']} | {cm(f['ate_rmse_m'])} / {cm(f['p95_pos_err_m'])} cm | "
          f"{cm(d['ate_rmse_m'])} cm ({d['ate_over_floor']:.2f}x) / {cm(d['p95_pos_err_m'])} cm / {d['p95_yaw_err_deg']:.2f} deg / {cm(d['max_pos_err_m'])} cm | "
          f"{own} | {rel} | {g['succeeded']}/{g['trials']} | {d['updates_per_s']:.0f} |")
json.dump(figures, open(f"{out}/figures.json", "w"), indent=1)
if not check:
    sys.exit(0)
claimed, bad = json.load(open(check)), []
for log, c in claimed.items():
    m = figures[log]
    for name, cv in c["variants"].items():
        mv = m["variants"][name]
        if "unusable" in cv:
            if "unusable" not in mv: bad.append(f"{log} {name}: localised, claimed unusable")
            continue
        for k in ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor"):
            if mv[k] > 1.5 * cv[k]: bad.append(f"{log} {name} {k}: {mv[k]:.4f} > 1.5 x {cv[k]:.4f}")
        if mv["relocalizations"] > cv["relocalizations"]: bad.append(f"{log} {name} relocalisations {mv['relocalizations']} > {cv['relocalizations']}")
    fail, cfail = 20 - m["global_succeeded"], 20 - c["global_succeeded"]
    if fail > max(cfail + 1, math.floor(1.5 * cfail)): bad.append(f"{log} global {m['global_succeeded']}/20 < claimed {c['global_succeeded']}/20")
    print(f"{log}: claimed drift ATE {cm(c['variants']['drift']['ate_rmse_m'])} cm, measured {cm(m['variants']['drift']['ate_rmse_m'])} cm; "
          f"global claimed {c['global_succeeded']}, measured {m['global_succeeded']}", file=sys.stderr)
if bad:
    print("\n".join(["regressed:"] + bad), file=sys.stderr)
    sys.exit(1)
print("all claimed real-log figures hold", file=sys.stderr)
PY
