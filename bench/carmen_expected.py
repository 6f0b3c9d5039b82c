#!/usr/bin/env python3
"""Re-measures the figures the real-log tests check against (tests/cli/eval_carmen_expected.json,
tests/cli/carmen_matrix_expected.json) with the polyloc given, keeping each log's arguments.

Run it after a change to the localiser that moves the figures on purpose, read the diff it prints
(old -> new, worse ones marked), and commit the files with the change that moved them.

  bench/carmen_expected.py build/bin/polyloc [--only aces,csail] [--matrix] [--dry-run]
"""
import argparse
import json
import os
import subprocess
import sys
import time

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(SRC, "..", "shared", "data", "carmen")
EVAL = os.path.join(SRC, "tests", "cli", "eval_carmen_expected.json")
MATRIX = os.path.join(SRC, "tests", "cli", "carmen_matrix_expected.json")
CASE_KEYS = ("ate_rmse_m", "p95_pos_err_m", "max_pos_err_m", "ate_over_floor")
COUNT_KEYS = ("frames_tracking_beyond_0_5m", "unannounced_jumps")


def run(polyloc, name, args):
    log = os.path.join(DATA, f"{name}-corrected.log.gz")
    t0 = time.time()
    out = subprocess.run([polyloc, "eval", "carmen", "--log", log, *args, "--json"], check=True,
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout
    print(f"  {name}: {time.time() - t0:.0f} s", file=sys.stderr)
    return json.loads(out)


def case_figures(c, keys):
    if c.get("unusable"):
        return {"unusable": c["unusable"]}
    f = {k: round(c[k], 4) for k in keys}
    f.update({k: c[k] for k in COUNT_KEYS})
    f["relocalizations"] = c["counters"]["relocalizations"]
    return f


def diff(name, old, new):
    for case, nv in new.get("cases", {}).items():
        ov = old.get("cases", {}).get(case, {})
        for k, v in nv.items():
            o = ov.get(k)
            if o != v:
                worse = isinstance(v, (int, float)) and isinstance(o, (int, float)) and v > o * (1.4 if k in CASE_KEYS else 1)
                print(f"{name} {case} {k}: {o} -> {v}{'   WORSE' if worse else ''}")
    for k in ("floor_m", "global"):
        if k in new and old.get(k) != new[k]:
            print(f"{name} {k}: {old.get(k)} -> {new[k]}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("polyloc")
    p.add_argument("--only", default="", help="comma-separated logs (default: every log in the file)")
    p.add_argument("--matrix", action="store_true", help="carmen_matrix_expected.json instead of eval_carmen's")
    p.add_argument("--dry-run", action="store_true", help="print the diff, write nothing")
    a = p.parse_args()
    path = MATRIX if a.matrix else EVAL
    expected = json.load(open(path))
    only = [n for n in a.only.split(",") if n]
    for name, e in expected.items():
        if only and name not in only:
            continue
        j = run(a.polyloc, name, e["args"])
        new = {"args": e["args"]}
        if not a.matrix:
            m = j["maps"][0]
            new["floor_m"] = round(m["floor"]["ate_rmse_m"], 4)
        keys = CASE_KEYS if not a.matrix else ("ate_rmse_m", "p95_pos_err_m", "ate_over_floor")
        new["cases"] = {c["name"]: case_figures(c, keys) for c in j["cases"]}
        if not a.matrix:
            g = j["maps"][0]["global"]
            new["global"] = {"trials": g["trials"], "succeeded": g["succeeded"]}
        for k, v in e.items():  # keys this script does not measure are kept
            new.setdefault(k, v)
        diff(name, e, new)
        expected[name] = new
        if not a.dry_run:
            with open(path, "w") as f:
                json.dump(expected, f, indent=1)
                f.write("\n")


if __name__ == "__main__":
    main()
