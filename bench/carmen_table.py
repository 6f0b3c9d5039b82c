#!/usr/bin/python3
"""The tables of bench/carmen_table.sh from OUT/<log>.json (polyloc eval carmen --json), the
figures file OUT/figures.json, and with a CHECK file the 1.5x regression check.

usage: carmen_table.py OUT [CHECK] LOG...
"""
import json
import math
import sys
from collections import defaultdict


def cm(x):
    return "n/a" if x is None else f"{100 * x:.1f}"


def ratio(x):
    return "n/a" if x is None else f"{x:.2f}"


def main():
    out, check, logs = sys.argv[1], sys.argv[2], sys.argv[3:]
    figures, worst = {}, []
    by_level = defaultdict(list)  # (drift, decimate) -> ratios over logs and maps
    print("| log | map | floor cm (bias cm) | cases | ATE / floor: median, worst (case) | tracking > 0.5 m | unannounced jumps | NEES mean (median over cases) | global |")
    print("| --- | --- | ---: | ---: | --- | ---: | ---: | ---: | ---: |")
    for log in logs:
        j = json.load(open(f"{out}/{log}.json"))
        figures[log] = {"maps": {}, "cases": {}}
        for m in j["maps"]:
            style = m["style"]
            cases = [c for c in j["cases"] if c["map"] == style and c.get("ate_rmse_m") is not None]
            ratios = sorted((c.get("ate_over_floor") or math.inf, c["name"]) for c in cases)
            tb = sum(c["frames_tracking_beyond_0_5m"] for c in cases)
            uj = sum(c["unannounced_jumps"] for c in cases)
            nees = sorted(c["nees"]["mean"] for c in cases if c["nees"]["mean"] is not None)
            g = m["global"]
            med = ratios[len(ratios) // 2][0] if ratios else None
            print(f"| {log} | {style} | {cm(m['floor']['ate_rmse_m'])} ({cm(m['floor']['range_bias_m'])}) | {len(cases)} | "
                  f"{ratio(med)}, {ratio(ratios[-1][0]) if ratios else 'n/a'} ({ratios[-1][1] if ratios else ''}) | {tb} | {uj} | "
                  f"{nees[len(nees) // 2]:.1f} | {g['succeeded']}/{g['trials']} |" if nees else "")
            figures[log]["maps"][style] = {"floor_m": m["floor"]["ate_rmse_m"], "global_succeeded": g["succeeded"], "global_trials": g["trials"]}
        for c in j["cases"]:
            if c.get("ate_rmse_m") is None:
                figures[log]["cases"][c["name"]] = {"unusable": c.get("unusable", "no estimate")}
                continue
            f = {k: c[k] for k in ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor",
                                   "frames_tracking_beyond_0_5m", "unannounced_jumps")}
            f["relocalizations"] = c["counters"]["relocalizations"]
            figures[log]["cases"][c["name"]] = f
            if c["odometry"] != "own":
                by_level[(c["odometry"], c["decimate"])].append(c["ate_over_floor"])
                worst.append((c["ate_over_floor"], f"{log} {c['name']}"))
    print()
    print("| drift | every | cases | ATE / floor: median | p90 | worst | within 1.5x |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for (drift, dec), rs in sorted(by_level.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        rs = sorted(r for r in rs if r is not None)
        if not rs:
            continue
        within = sum(r <= 1.5 for r in rs)
        print(f"| {drift} | {dec} | {len(rs)} | {rs[len(rs) // 2]:.2f} | {rs[min(len(rs) - 1, int(0.9 * len(rs)))]:.2f} | "
              f"{rs[-1]:.2f} | {within}/{len(rs)} |")
    worst.sort(reverse=True)
    print("\nworst cases: " + ", ".join(f"{n} {r:.2f}x" for r, n in worst[:8]), file=sys.stderr)
    json.dump(figures, open(f"{out}/figures.json", "w"), indent=1)
    if not check:
        return 0
    claimed, bad = json.load(open(check)), []
    for log, c in claimed.items():
        if log not in figures:
            continue
        m = figures[log]
        for name, cv in c["cases"].items():
            mv = m["cases"].get(name)
            if mv is None:
                bad.append(f"{log} {name}: not measured")
                continue
            if "unusable" in cv or "unusable" in mv:
                if ("unusable" in cv) != ("unusable" in mv):
                    bad.append(f"{log} {name}: unusable {mv.get('unusable')} vs claimed {cv.get('unusable')}")
                continue
            for k in ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor"):
                if mv[k] > 1.5 * cv[k]:
                    bad.append(f"{log} {name} {k}: {mv[k]:.4f} > 1.5 x {cv[k]:.4f}")
            for k in ("frames_tracking_beyond_0_5m", "unannounced_jumps", "relocalizations"):
                if mv[k] > max(cv[k] + 1, math.floor(1.5 * cv[k])):
                    bad.append(f"{log} {name} {k}: {mv[k]} > claimed {cv[k]}")
        for style, gv in c["maps"].items():
            mg = m["maps"].get(style)
            if mg is None:
                continue
            fail, cfail = mg["global_trials"] - mg["global_succeeded"], gv["global_trials"] - gv["global_succeeded"]
            if fail > max(cfail + 1, math.floor(1.5 * cfail)):
                bad.append(f"{log} {style} global {mg['global_succeeded']}/{mg['global_trials']} < claimed {gv['global_succeeded']}")
    if bad:
        print("\n".join(["regressed:"] + bad), file=sys.stderr)
        return 1
    print("all claimed real-log figures hold", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
