#!/usr/bin/env bash
# Cross-check of our MCAP and CDR against independent implementations: the fixture writer puts
# every message type with known values into MCAP files (zstd, lz4, uncompressed), and
# tests/js/check_mcap.mjs reads them with @mcap/core and @foxglove/rosmsg2-serialization
# (versions pinned in tests/js/package-lock.json, installed with npm ci when missing or stale:
# npm_deps.sh).
# Usage: bash mcap_crosscheck.sh <path-to-polyloc> <source-dir> <path-to-mcap_fixture_writer>
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
source_dir=$2
writer=${3:?usage: mcap_crosscheck.sh <polyloc> <source-dir> <mcap_fixture_writer>}
js="$source_dir/tests/js"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }
source "$source_dir/tests/cli/npm_deps.sh"
npm_deps "$js" "the MCAP cross-check"

passed=0
for compression in zstd lz4 none; do
  "$writer" "$tmp/$compression.mcap" "$tmp/$compression.json" "$compression" ||
    fail "fixture writer failed for compression $compression"
  node "$js/check_mcap.mjs" "$tmp/$compression.mcap" "$tmp/$compression.json" ||
    fail "cross-check of the $compression file found differences (above)"
  passed=$((passed + 1))
done
echo "mcap_crosscheck: $passed passed, 0 failed"
