#!/bin/bash
# One name, one meaning (README "The CLI"): every renamed option's old name still works in its
# command, rewritten to the new one with a warning naming both (as "--old V" and "--old=V"); the
# new name warns of nothing; the same old name in a command where it keeps its meaning (eval's
# --rounds) is not rewritten. --help stops each run after parsing.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR
POLYLOC=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
while read -r cmd old new value; do
  [ -n "$cmd" ] || continue
  cmd=${cmd//_/ }
  for form in "$old $value" "$old=$value"; do
    # shellcheck disable=SC2086
    "$POLYLOC" $cmd $form --help > /dev/null 2> "$tmp/err" || { cat "$tmp/err" >&2; echo "$cmd $form: refused" >&2; exit 1; }
    grep -q -- "$old is deprecated, use $new" "$tmp/err" || { cat "$tmp/err" >&2; echo "$cmd $form: no warning" >&2; exit 1; }
  done
  # shellcheck disable=SC2086
  "$POLYLOC" $cmd "$new" "$value" --help > /dev/null 2> "$tmp/err"
  if grep -q "deprecated" "$tmp/err"; then cat "$tmp/err" >&2; echo "$cmd $new: warned" >&2; exit 1; fi
done <<'LIST'
bench_raycast --height --sensor-height 0.3
bench_bsp --height --sensor-height 0.3
bench_maps --height --sensor-height 0.3
bench_mcl --height --sensor-height 0.3
demo --height --sensor-height 0.3
map_navgrid --height --robot-height 1.2
map_navgrid --clearance --floor-clearance 0.05
bench_bsp --clearance --robot-radius 0.3
bench_bsp --grid --grid-resolutions 0.05,0.1
bench_ipc --rounds --turns 100
LIST
"$POLYLOC" eval kidnap --rounds 5 --help > /dev/null 2> "$tmp/err"
if grep -q "deprecated" "$tmp/err"; then cat "$tmp/err" >&2; echo "eval's --rounds was rewritten" >&2; exit 1; fi
echo "renamed options ok"
