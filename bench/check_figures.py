#!/usr/bin/env python3
"""Re-measure every figure that docs/benchmarks.md and README.md claim and fail on a 1.5x regression.

The claims are data (docs/figures.json): command groups (one command each, run once) and figures
(a value in a group's JSON, the claimed value, its direction). This script runs the selected groups,
reads the figures, prints `figure | claimed | measured | ratio | verdict` as Markdown on stdout,
writes OUT_DIR/figures_measured.json and exits 1 when a figure regressed (or a group failed).

  bench/check_figures.py BUILD_DIR OUT_DIR [--only REGEX] [--list] [--with-slow]

--only keeps the figures whose id or group matches REGEX (plus the groups they need);
--with-slow adds the groups marked slow (the polylocd soak and end-to-end latency, real time).
Stdlib only: runs under any python3.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIGURES = os.path.join(REPO, "docs", "figures.json")


def expand(text, build, out):
    """Placeholders of figures.json: {build} the build directory, {out} the output directory, {repo}."""
    return text.replace("{build}", build).replace("{out}", out).replace("{repo}", REPO)


def derive_configs(group, build, out):
    """Write the config variants a group needs (e.g. `refine: {enabled: false}` for "MCL only").
    The copy lives in OUT_DIR, so its relative paths (`: ../`) are made absolute, as e2e_latency.sh does."""
    for d in group.get("derive", []):
        text = open(os.path.join(REPO, d["from"])).read()
        base = os.path.dirname(os.path.join(REPO, d["from"]))
        text = text.replace(": ../", ": " + os.path.dirname(base) + "/")
        for old, new in d["replace"]:
            if old not in text:
                raise SystemExit(f"check_figures: '{old}' not in {d['from']} (figures.json derive of {group['name']})")
            text = text.replace(old, new)
        with open(expand(d["to"], build, out), "w") as f:
            f.write(text)


def run_group(group, build, out):
    """Run the group's command once: stdout to OUT/<name>.json (or `stdout`), stderr to OUT/<name>.err;
    its JSON is stdout or the file `json` names. Returns (exit status, wall seconds, parsed JSON or None)."""
    derive_configs(group, build, out)
    cmd = [expand(a, build, out) for a in group["cmd"]]
    stdout_path = expand(group.get("stdout", os.path.join(out, group["name"] + ".json")), build, out)
    json_path = expand(group.get("json", stdout_path), build, out)
    if os.path.exists(json_path):  # a failed run must not be judged on an earlier run's JSON
        os.remove(json_path)
    start = time.monotonic()
    with open(stdout_path, "w") as so, open(os.path.join(out, group["name"] + ".err"), "w") as se:
        rc = subprocess.call(cmd, stdout=so, stderr=se, cwd=REPO)
    wall = time.monotonic() - start
    try:
        data = json.load(open(json_path))
    except (OSError, ValueError):
        data = None
    return rc, wall, data


def lookup(data, path):
    """A path is a list of steps: a key or an index, or {"key": value} for the list item whose key
    has that value (Google Benchmark's `benchmarks` list, by `name`)."""
    for step in path:
        if isinstance(step, dict):
            (k, v), = step.items()
            data = next(item for item in data if item.get(k) == v)
        else:
            data = data[step]
    return data


def csv_growth(path, column, t0):
    """Last value of a CSV column minus the first sampled at t_s >= t0 (the soak's RSS growth)."""
    import csv
    rows = [r for r in csv.DictReader(open(path)) if float(r["t_s"]) >= t0]
    return float(rows[-1][column]) - float(rows[0][column])


def measure(fig, results, build, out):
    """The measured value of a figure, in the units of the JSON (None when it could not be read)."""
    def value(group, path, file=None):
        rc, wall, data = results[group]
        try:
            if path[0] == "$wall_s":
                return wall
            if path[0] == "$exit_status":
                return rc
            if path[0] == "$csv_growth":
                return csv_growth(expand(path[1], build, out), path[2], path[3])
            if file:  # a group that writes several JSON files (carmen: one per log)
                data = json.load(open(expand(file, build, out)))
            return float(lookup(data, path))
        except (OSError, ValueError, KeyError, IndexError, TypeError, StopIteration):
            return None
    m = value(fig["group"], fig["path"], fig.get("file"))
    if m is not None and "divide_by" in fig:  # a ratio of two values, e.g. 2 threads / 1 thread
        d = value(fig["divide_by"].get("group", fig["group"]), fig["divide_by"]["path"])
        m = None if not d else m / d
    return m


def judge(fig, m):
    """Ratio (> 1: worse than claimed) and verdict, by the rules that figures.json's `rules` state:
    success counts (`of`) compare failures, integer counts may grow to max(c + 1, floor(1.5 c)),
    `complement` fractions compare the share that failed (1 - x), a claimed 0 may grow by `allow`,
    otherwise 1.5x (or `allow`, whichever is larger) in the direction the figure states."""
    c, tol = fig["claimed"], 1.5
    if m is None:
        return None, "NOT MEASURED"
    if "of" in fig:  # k of n: failures
        c, m = fig["of"] - c, fig["of"] - m
    if fig.get("complement"):  # 96.7% removed -> 3.3% left
        c, m = 1 - c, 1 - m
    direction = "lower_is_better" if "of" in fig or fig.get("complement") else fig["direction"]
    if direction == "lower_is_better":
        ratio = m / c if c else None
        if c == 0 and "allow" in fig:  # 0 mismatches, 0 frames dropped: the stated allowance
            limit = fig["allow"]
        elif fig["kind"] == "count":  # integers (failures, rounds): as bench/carmen_table.sh
            limit = max(c + 1, math.floor(tol * c))
        else:
            limit = max(tol * c, c + fig.get("allow", 0))
    elif direction == "higher_is_better":
        ratio = c / m if m > 0 else math.inf
        return ratio, "REGRESSED" if ratio > tol else "ok"
    else:  # two_sided: a descriptive figure (mean range) that must not move by 1.5x either way
        ratio = max(m / c, c / m) if m > 0 else math.inf
        return ratio, "CHANGED" if ratio > tol else "ok"
    if m > limit + 1e-12:
        return ratio, "REGRESSED"
    return ratio, "ok" if ratio is None or ratio <= tol else "ok (allowance)"


def fmt(x, fig):
    if x is None:
        return "n/a"
    x *= fig.get("scale", 1)
    text = f"{x:.4g}" if abs(x) < 1e5 else f"{x:.3e}"
    return f"{text} {fig['unit']}".rstrip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("out")
    ap.add_argument("--only", help="figures whose id or group matches this regular expression")
    ap.add_argument("--list", action="store_true", help="list the groups and figures, run nothing")
    ap.add_argument("--with-slow", action="store_true", help="also the slow groups (soak, e2e latency)")
    args = ap.parse_args()
    spec = json.load(open(FIGURES))
    groups = {g["name"]: g for g in spec["groups"]}
    figs = [f for f in spec["figures"]
            if (args.with_slow or not groups[f["group"]].get("slow"))
            and (not args.only or re.search(args.only, f["id"]) or re.search(args.only, f["group"]))]
    # Groups to run, in figures.json's order: those of the figures, the ones divide_by reads, and
    # what they need (a simulated recording), unless that recording is already in OUT_DIR.
    wanted = {f["group"] for f in figs} | {f["divide_by"]["group"] for f in figs if "group" in f.get("divide_by", {})}
    build, out = os.path.abspath(args.build), os.path.abspath(args.out)
    for name in list(wanted):
        for need in groups[name].get("needs", []):
            if not os.path.exists(expand(groups[need]["creates"], build, out)):
                wanted.add(need)
    order = [g for g in spec["groups"] if g["name"] in wanted]
    if args.list:
        for g in order:
            print(f"{g['name']}{' (slow)' if g.get('slow') else ''}: {' '.join(g['cmd'])}")
            for f in figs:
                if f["group"] == g["name"]:
                    print(f"  {f['id']}: {fmt(f['claimed'], f)} ({f['direction']}, {f['kind']})")
        return 0
    os.makedirs(out, exist_ok=True)
    results, failed_groups, t0, load0 = {}, [], time.monotonic(), os.getloadavg()[0]
    for i, g in enumerate(order, 1):
        shown = " ".join(g["cmd"]).replace("{build}/bin/", "")
        print(f"[{i}/{len(order)}] {shown} ...", end="", file=sys.stderr, flush=True)
        results[g["name"]] = run_group(g, build, out)
        rc, wall, data = results[g["name"]]
        ok = rc == 0 or g.get("exit_is_figure")
        print(f" {wall:.0f} s" + ("" if ok else f" FAILED (exit {rc}, see {out}/{g['name']}.err)"), file=sys.stderr, flush=True)
        if not ok:
            failed_groups.append(g["name"])
    rows, bad = [], []
    print("| figure | claimed | measured | ratio | verdict |")
    print("| --- | ---: | ---: | ---: | --- |")
    for f in figs:
        m = measure(f, results, build, out)
        ratio, verdict = judge(f, m)
        rows.append({**f, "measured": m, "ratio": ratio, "verdict": verdict})
        if not verdict.startswith("ok"):
            bad.append(f["id"])
        print(f"| {f['id']} | {fmt(f['claimed'], f)} | {fmt(m, f)} | {'' if ratio is None else f'{ratio:.2f}'} | {verdict} |")
    # Speed figures read low on a loaded machine (the doc's were taken on 2 quiet cores): say how loaded.
    load = f"load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end on {os.cpu_count()} CPUs"
    json.dump({"build": build, "wall_s": time.monotonic() - t0, "load": load, "failed_groups": failed_groups,
               "group_wall_s": {k: v[1] for k, v in results.items()}, "figures": rows},
              open(os.path.join(out, "figures_measured.json"), "w"), indent=1)
    print(f"{len(figs) - len(bad)} of {len(figs)} figures hold; {time.monotonic() - t0:.0f} s; "
          f"{load}; {out}/figures_measured.json", file=sys.stderr)
    if bad or failed_groups:
        print("regressed or not measured: " + ", ".join(bad + [f"group {g}" for g in failed_groups]), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
