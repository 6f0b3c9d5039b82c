#!/usr/bin/env bash
# polyloc relocalize across MPI ranks: `mpirun -np 2` (oversubscribed, as root) on two 20 s lab
# tours split into 10 s segments with 3 s warm-up (4 tasks over 2 ranks) merges into the same
# outputs as one process with the same segments: trajectories within 1 mm (same seeds), one
# summary that says which rank ran what. Then whole recordings with one unreadable among them:
# the rank that ran it reports it, rank 0's summary lists it as missing, the others are written,
# the exit status is not 0. Added by tests/CMakeLists.txt only with POLYLOC_MPI.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1 src=$2 mpirun=${3:-mpirun}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$src"
"$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 20 --out "$tmp/a.mcap" >/dev/null
"$polyloc" simulate --scenario maps/scenarios/lab_tour.yaml --duration 20 --seed 2 --out "$tmp/b.mcap" >/dev/null
args=(relocalize --config maps/config/lab.yaml --input "$tmp/a.mcap" "$tmp/b.mcap" --segment 10 --warmup 3)
"$polyloc" "${args[@]}" --out "$tmp/one" --jobs 2 >/dev/null
"$mpirun" --allow-run-as-root --oversubscribe -np 2 "$polyloc" "${args[@]}" --out "$tmp/mpi" --jobs 1 >"$tmp/out" 2>"$tmp/err" \
  || { cat "$tmp/out" "$tmp/err" >&2; exit 1; }
echo "not a recording" > "$tmp/bad.mcap"
cp "$tmp/a.mcap" "$tmp/c.mcap"  # four tasks, the bad one (smallest, dealt last) on rank 1
if "$mpirun" --allow-run-as-root --oversubscribe -np 2 "$polyloc" relocalize --config maps/config/lab.yaml \
    --input "$tmp/a.mcap" "$tmp/bad.mcap" "$tmp/b.mcap" "$tmp/c.mcap" --out "$tmp/bad" --jobs 1 >"$tmp/out2" 2>"$tmp/err2"; then
  echo "expected a failure with a bad input under mpirun" >&2; exit 1
fi
grep -q "bad.mcap" "$tmp/err2"
python3 - "$tmp" <<'PY'
import json, sys
tmp = sys.argv[1]
one, mpi = (json.load(open(f"{tmp}/{d}/summary.json")) for d in ("one", "mpi"))
assert mpi["cluster"] == "mpi" and mpi["ranks"] == 2 and mpi["tasks"] == 4, mpi
assert mpi["all_succeeded"] and not mpi["missing"], mpi
assert one["cluster"] == "single" and one["ranks"] == 1
def tum(path):
    return [list(map(float, l.split())) for l in open(path) if l.strip() and not l.startswith("#")]
ranks = set()
for name in ("a", "b"):
    s = json.load(open(f"{tmp}/mpi/{name}/summary.json"))
    assert s["segments"] == 2, s["segments"]
    ranks |= set(s["ranks"])
    a, b = tum(f"{tmp}/one/{name}/trajectory.tum"), tum(f"{tmp}/mpi/{name}/trajectory.tum")
    assert len(a) == len(b) > 20, (len(a), len(b))
    assert all(x[0] <= y[0] for x, y in zip(b, b[1:])), "not in time order"
    worst = max(max(abs(p - q) for p, q in zip(x[1:4], y[1:4])) for x, y in zip(a, b))
    assert all(x[0] == y[0] for x, y in zip(a, b)) and worst < 1e-3, worst
    print(f"{name}: {len(a)} poses, worst difference {worst:.2e} m, ATE {s['ate_rmse_m']:.4f} m")
assert ranks == {0, 1}, ranks
bad = json.load(open(f"{tmp}/bad/summary.json"))
assert bad["ranks"] == 2 and bad["succeeded"] == 3 and not bad["all_succeeded"], bad
miss = bad["missing"]
assert len(miss) == 1 and miss[0]["input"].endswith("bad.mcap") and miss[0]["rank"] == 1, miss
assert [i["status"] for i in bad["inputs"]] == ["ok", "failed", "ok", "ok"], [i["status"] for i in bad["inputs"]]
assert open(f"{tmp}/bad/a/trajectory.tum").read() == open(f"{tmp}/bad/c/trajectory.tum").read()
PY
