#!/usr/bin/env bash
# The pinned JS packages of tests/js (package-lock.json), installed with `npm ci` when
# node_modules is missing or stale. Sourced by the tests that run tests/js checks
# (mcap_crosscheck.sh, live_view.sh):
#   source "$source_dir/tests/cli/npm_deps.sh"; npm_deps "$source_dir/tests/js" "the MCAP cross-check"
# Fails (exit 1, `FAIL: ...`) naming what is missing; `make deps` installs node and npm.
# Run directly (`bash npm_deps.sh <polyloc> <source-dir>`) it just installs them.

npm_deps() {
  local js=$1 what=${2:-the JS checks} log
  command -v node >/dev/null || { echo "FAIL: node is not on PATH (needed for $what; make deps installs it)" >&2; exit 1; }
  command -v npm >/dev/null || { echo "FAIL: npm is not on PATH (needed for $what; make deps installs it)" >&2; exit 1; }
  log=$(mktemp)
  # npm writes node_modules/.package-lock.json on install: older than the lock file means stale.
  # The lock keeps two test runs (two build dirs, or two tests) from installing into the same
  # folder at once.
  if ! (
    flock 9
    stamp="$js/node_modules/.package-lock.json"
    if [ ! -f "$stamp" ] || [ "$js/package-lock.json" -nt "$stamp" ] || [ "$js/package.json" -nt "$stamp" ]; then
      (cd "$js" && npm ci --no-audit --no-fund --loglevel=error) >"$log" 2>&1 || exit 1
    fi
  ) 9>"${TMPDIR:-/tmp}/polyloc-npm-$(id -u).lock"; then
    cat "$log" >&2
    rm -f "$log"
    echo "FAIL: npm ci in $js failed (output above)" >&2
    exit 1
  fi
  rm -f "$log"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  set -euo pipefail
  npm_deps "${2:?usage: npm_deps.sh <polyloc> <source-dir>}/tests/js" "tests/js"
  echo "npm_deps: $2/tests/js/node_modules up to date"
fi
