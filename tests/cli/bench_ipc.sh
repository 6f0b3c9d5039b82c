#!/usr/bin/env bash
# polyloc bench ipc as a user runs it (few messages): one JSON object with every transport's
# percentiles, all positive, and the ratio the issue's target is about.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tmp_out=$tmp/out tmp_err=$tmp/err
out=$("$polyloc" bench ipc --messages 300 --warmup 20 --period-us 100 --json)
echo "$out"
python3 - "$out" <<'PY'
import json, sys
j = json.loads(sys.argv[1])
assert j["message_bytes"] == 2180 and j["messages"] == 300, j
for name in ("shm", "uds", "tcp", "shm_spin"):
    t = j["transports"][name]
    for key in ("p50_us", "p99_us", "p999_us", "max_us", "send_p50_us"):
        assert t[key] > 0, (name, key, t)
    assert t["p50_us"] <= t["p99_us"] <= t["p999_us"] <= t["max_us"], (name, t)
    # Sockets lose nothing; a shm reader descheduled for longer than its ring lasts skips ahead.
    assert t["received"] + t["lost"] == 300 and t["received"] > 0, (name, t)
    assert name.startswith("shm") or t["lost"] == 0, (name, t)
assert j["ratio_shm_p99_to_uds_p99"] > 0, j
assert isinstance(j["target_met"], bool), j
PY
# Another message size.
out=$("$polyloc" bench ipc --messages 50 --warmup 5 --bytes 65536 --json)
grep -q '"message_bytes":65536' <<<"$out"
# --rounds was renamed --turns (eval's --rounds are filter rounds): the old name still runs, warned.
"$polyloc" bench ipc --messages 20 --warmup 2 --rounds 2 --json > "$tmp_out" 2> "$tmp_err"
grep -q "warning: --rounds is deprecated, use --turns" "$tmp_err"
grep -q '"message_bytes":' "$tmp_out"
# Too small a message is an error that names the option.
if err=$("$polyloc" bench ipc --bytes 8 2>&1); then exit 1; fi
grep -q -- '--bytes' <<<"$err"
echo OK
