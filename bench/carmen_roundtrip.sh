#!/usr/bin/env bash
# The thesis built simulation worlds from 2D grid maps; this closes that loop on the office: a
# simulated patrol (taser rig: two LMS200, people walking, chairs moved) written as a corrected
# CARMEN log (laser poses from ground truth, bench/carmen_from_run.py), mapped and extruded by
# `polyloc map extrude --carmen`, and a second patrol (other seed) localised on the extruded map,
# beside the same patrol on the original mesh. Prints one JSON object; OUT has the log, the grid
# (PGM + YAML), the extruded OBJ and a PNG of the localisation on it.
#   [RES=0.05] [UNKNOWN_OCCUPIED=1] bench/carmen_roundtrip.sh [BUILD_DIR] [DURATION_S] [OUT_DIR] [PYTHON]
set -euo pipefail
build=${1:-build}
duration=${2:-0}   # 0: the scenario's (132 s)
out=${3:-$build/carmen_roundtrip}
python=${4:-/usr/bin/python3}
mkdir -p "$out"
d=(); [ "$duration" != 0 ] && d=(--duration "$duration")
u=(); [ "${UNKNOWN_OCCUPIED:-0}" = 1 ] && u=(--unknown-occupied)   # cells never seen become walls
"$build/bin/polyloc" simulate --scenario maps/scenarios/office_patrol.yaml "${d[@]}" --out "$out/map_run.mcap" >/dev/null
"$build/bin/polyloc" simulate --scenario maps/scenarios/office_patrol.yaml "${d[@]}" --seed 2 --out "$out/loc_run.mcap" >/dev/null
# The taser's mounts (maps/rigs/taser.yaml): name:x:y:yaw_deg.
PYTHONPATH="$build/python" "$python" bench/carmen_from_run.py "$out/map_run.mcap" "$out/run.log" \
  lms_front:0.33:0:0 lms_rear:-0.33:0:180
"$build/bin/polyloc" map extrude --carmen "$out/run.log" --resolution "${RES:-0.05}" --wall-height 2.5 "${u[@]}" \
  --out "$out/extruded.obj" --save-grid "$out/grid.yaml" --json >"$out/extrude.json"
"$build/bin/polyloc" localize --config maps/config/office.yaml --map "$out/extruded.obj" --input "$out/loc_run.mcap" \
  --plot "$out/extruded_localize.png" --json 2>/dev/null >"$out/localize_extruded.json"
"$build/bin/polyloc" localize --config maps/config/office.yaml --input "$out/loc_run.mcap" --json 2>/dev/null \
  >"$out/localize_original.json"
"$python" - "$out" <<'PY'
import json, sys
out = sys.argv[1]
e = json.load(open(f"{out}/extrude.json"))
x = json.load(open(f"{out}/localize_extruded.json"))
o = json.load(open(f"{out}/localize_original.json"))
print(json.dumps({
    "resolution_m": e["resolution_m"], "scans_used": e["scans_used"], "scans_skipped": e["scans_skipped"], "occupied_cells": e["occupied_cells"],
    "cells": [e["cells_x"], e["cells_y"]], "boxes": e["boxes"], "triangles": e["triangles"], "closed": e["closed"],
    "extruded": {k: x[k] for k in ("ate_rmse_m", "p95_pos_err_m", "yaw_rmse_deg", "updates", "frames")},
    "original": {k: o[k] for k in ("ate_rmse_m", "p95_pos_err_m", "yaw_rmse_deg", "updates", "frames")},
    "out": out}))
PY
