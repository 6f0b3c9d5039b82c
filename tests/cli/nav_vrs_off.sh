#!/bin/bash
# What the VRS is for, measured: the same two missions in lab 3 (to the shelves, then to the
# north bench past the island and its chairs) with the VRS and with only the level scanners
# (--vrs off: what a 2D controller sees, on a map sliced at their height). With the VRS both are
# reached without collision; without it the robot drives into a chair seat the level scanners
# see only the legs of, and the collision is named with its place.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
PY=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/lab3.yaml" <<YAML
base: $SRC/maps/scenarios/lab_nav.yaml
route:
  waypoints: [[16.0, 1.75]]
navigation:
  zones: $SRC/maps/nav/lab.yaml
  goals: [lab 3 shelves, lab 3 bench]
  mission_timeout: 60
  vrs_sources: [{sensor: tof_front, mode: off}]
YAML
"$POLYLOC" eval nav --scenario "$tmp/lab3.yaml" --missions 2 --json --quiet > "$tmp/on.json"
"$POLYLOC" eval nav --scenario "$tmp/lab3.yaml" --missions 2 --vrs off --json --quiet --plot "$tmp/off.png" > "$tmp/off.json"
"$PY" - "$tmp/on.json" "$tmp/off.json" <<'PYEOF'
import json, sys
on, off = (json.load(open(f)) for f in sys.argv[1:3])
for j in (on, off):
    print(j["vrs"], {k: j[k] for k in ("reached", "collisions", "collisions_by_label", "danger_entries", "sim_s")})
assert on["reached"] == 2 and on["collisions"] == 0 and on["danger_entries"] == 0, on
assert off["collisions"] >= 1, off
hits = [c for m in off["per_mission"] for c in m["collisions"]]
# A chair seat or a table top: above the level scanners (0.10 m), below the robot's top.
assert all(c["label"] in ("chair", "table") and 0.3 < c["where"][2] < 1.2 for c in hits), hits
assert off["reached"] < 2, off["per_mission"]
PYEOF
head -c 8 "$tmp/off.png" | od -An -c | grep -q "P   N   G"
echo "vrs off ok"
