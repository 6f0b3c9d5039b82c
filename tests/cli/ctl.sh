#!/usr/bin/env bash
# polyloc ctl without a polylocd: a refused connection, a wrong port and usage errors are
# errors (exit 1) that say what was wrong. The replies of a server are tested in
# tests/cpp/test_protocol_cli.cpp (in-process fake) and end to end with polylocd.
# Usage: bash ctl.sh <path-to-polyloc> <source-dir>
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
fail() { echo "FAIL: $*" >&2; exit 1; }

# A port nobody listens on: bound and released just now.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()')

expect_error() {  # expect_error "message part" ctl-args...
  local want=$1; shift
  local status=0 err
  err=$("$polyloc" ctl "$@" 2>&1 >/dev/null) || status=$?
  [[ $status -eq 1 ]] || fail "ctl $*: exit status $status, expected 1"
  grep -qF -- "$want" <<<"$err" || fail "ctl $*: message does not say '$want': $err"
}

expect_error "cannot connect to 127.0.0.1:$port: Connection refused" --port "$port" ping
expect_error "cannot connect to 127.0.0.1:$port: Connection refused" --port "$port" --json getpose
expect_error "cannot resolve no-such-host.invalid:$port" --host no-such-host.invalid --port "$port" ping
expect_error "--port 70000 is not a TCP port" --port 70000 ping
expect_error "unknown ctl command 'frobnicate'" --port "$port" frobnicate
expect_error "usage: polyloc ctl setpose X Y YAW_DEG" --port "$port" setpose 1 2
expect_error "YAW_DEG: 'north' is not a number" --port "$port" setpose 1 2 north
expect_error "setca: 'on' is not 0 or 1" --port "$port" setca on
expect_error "usage: polyloc ctl scan INDEX" --port "$port" scan
# --json prints nothing on stdout when it fails.
out=$("$polyloc" ctl --port "$port" --json status 2>/dev/null || true)
[[ -z $out ]] || fail "--json on error printed: $out"
echo "ctl: ok"
