#!/usr/bin/env bash
# polyloc map info, as a user types it: the error path for a missing file, the text report and
# --json on a small OBJ written here, and the bundled lab map if it is there.
# Usage: bash map_info.sh <path-to-polyloc> <source-dir>
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
source_dir=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

# A missing file: non-zero exit, and the message names the file.
if "$polyloc" map info "$tmp/no_such_map.obj" >"$tmp/out" 2>"$tmp/err"; then
  fail "missing file: exit status 0"
fi
grep -q "no_such_map.obj" "$tmp/err" || fail "missing file: message does not name it: $(cat "$tmp/err")"
grep -q "does not exist" "$tmp/err" || fail "missing file: message does not say why: $(cat "$tmp/err")"

# A unit cube of quads, counter-clockwise seen from outside: five in object wall_1, one in door_2.
cat >"$tmp/cube.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
v 0 0 1
v 1 0 1
v 0 1 1
v 1 1 1
o wall_1
f 1 3 4 2
f 5 6 8 7
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
o door_2
f 1 2 6 5
EOF

"$polyloc" map info "$tmp/cube.obj" >"$tmp/out"
grep -q "^triangles: 12$" "$tmp/out" || fail "text report: $(cat "$tmp/out")"
grep -q "^open edges: 0$" "$tmp/out" || fail "text report: $(cat "$tmp/out")"
grep -q "door: 2" "$tmp/out" || fail "text report labels: $(cat "$tmp/out")"

"$polyloc" map info "$tmp/cube.obj" --json --scale 2 --up-axis y >"$tmp/json"
python3 - "$tmp/json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["triangles"] == 12 and r["vertices"] == 8, r
assert r["open_edges"] == 0 and r["non_manifold_edges"] == 0 and r["inconsistent_edges"] == 0, r
assert r["degenerate_triangles"] == 0 and r["closed"] and r["consistent_winding"], r
assert r["labels"] == {"wall": 10, "door": 2}, r
# y up, scaled 2: map (x, y, z) = 2 * file (x, -z, y)
assert r["bounds"] == {"min": [0, -2, 0], "max": [2, 0, 2]}, r["bounds"]
EOF

# A bad option value is an error too.
if "$polyloc" map info "$tmp/cube.obj" --up-axis w >/dev/null 2>&1; then fail "--up-axis w accepted"; fi

# The bundled lab map, if it has been generated.
if [[ -f "$source_dir/maps/lab.obj" ]]; then
  "$polyloc" map info "$source_dir/maps/lab.obj" --json >"$tmp/lab.json"
  python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert r["triangles"] > 0, r' "$tmp/lab.json"
fi
echo "map_info: ok"
