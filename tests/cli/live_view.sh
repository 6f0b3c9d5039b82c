#!/bin/bash
# polylocd's live view end to end (service/live/, docs/live.md), with real clients: the protocol
# checks against the idle daemon (limits, refusals, malformed messages: check_live_protocol.mjs);
# then, while `polyloc play` feeds 20 s of the lab tour, Foxglove's own client subscribed to every
# channel (check_live_foxglove.mjs: decodes everything with the advertised schemas, poses against
# play's ground truth, its pose rate against polylocd's count), a viewer that stops reading
# (stall_live_client.mjs: polylocd must cut it off, and the others must not notice) and the page
# in headless Chromium (check_live_page.mjs). polylocd takes every frame unbroken and stops
# cleanly on SIGINT (what viewers cost it in latency and frames: bench/live_viewers.sh).
# Usage: bash live_view.sh <path-to-polyloc> <source-dir>   (polylocd is beside polyloc)
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
POLYLOC=$1
SRC=$2
POLYLOCD=$(dirname "$POLYLOC")/polylocd
PY=$(command -v python3)
cd "$SRC"
js=tests/js
tmp=$(mktemp -d)
instance=live_$$
pid=            # polylocd
bg=()           # background clients
cleanup() {
  for p in "${bg[@]}"; do kill "$p" 2>/dev/null || true; done
  [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null
  rm -rf "$tmp" "/dev/shm/polyloc.$instance"
}
trap cleanup EXIT

fail() { echo "FAIL: live_view: $*" >&2; exit 1; }
step() { echo "live_view: [${SECONDS}s] $*"; }
show() { echo "--- $1" >&2; tail -n "${3:-40}" "$2" >&2 || true; }
# polylocd must be alive; else its exit status (a signal: 128 + n) and its log.
alive() {
  kill -0 "$pid" 2>/dev/null && return 0
  local rc=0
  wait "$pid" || rc=$?
  pid=
  show "polylocd log (tail)" "$tmp/polylocd.log"
  fail "polylocd died $1 (exit status $rc$([ "$rc" -gt 128 ] && echo ", signal $(kill -l $((rc - 128)))"))"
}

source tests/cli/npm_deps.sh
npm_deps "$SRC/$js" "the live view test"
[ -x /usr/bin/chromium ] ||
  fail "/usr/bin/chromium is missing: the page check drives Debian's Chromium headless (make deps installs it: apt-get install chromium)"

# A config with tight viewer limits: 4 clients, 0.5 MiB queue, cut off after 2 s over it.
grep -q "^polylocd:" maps/config/lab.yaml || fail "maps/config/lab.yaml has no polylocd: section"
sed -e "s#\.\./lab\.obj#$SRC/maps/lab.obj#" -e "s#\.\./rigs/lisa\.yaml#$SRC/maps/rigs/lisa.yaml#" \
  -e "/^polylocd:/a\\  live: {max_clients: 4, max_queue: 0.5, stall_timeout: 2}" maps/config/lab.yaml > "$tmp/live.yaml"
"$POLYLOCD" --config "$tmp/live.yaml" --check > "$tmp/check.txt" 2>&1 || { show "polylocd --check" "$tmp/check.txt"; fail "test config rejected"; }

# A free port (bound and released); another process may take it in between: then retry.
for _ in 1 2 3; do
  port=$("$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()')
  "$POLYLOCD" --config "$tmp/live.yaml" --instance "$instance" --control-port 0 --live-port "$port" \
    --init 1.3,1.75,0 --threads 2 > "$tmp/polylocd.log" 2>&1 &
  pid=$!
  for _ in $(seq 300); do  # 30 s: map loading on a loaded machine
    grep -q "ready: rig\|cannot listen" "$tmp/polylocd.log" && break
    alive "while starting"
    sleep 0.1
  done
  grep -q "cannot listen" "$tmp/polylocd.log" || break
  kill -TERM "$pid"; wait "$pid" || true; pid=
  step "port $port taken meanwhile; another"
done
grep -q "live view on http://127.0.0.1:$port/" "$tmp/polylocd.log" || { show "polylocd log" "$tmp/polylocd.log"; fail "polylocd did not start its live view on port $port"; }
url=http://127.0.0.1:$port/
"$PY" - "$url" <<'PYEOF' || { show "polylocd log" "$tmp/polylocd.log"; fail "no HTTP answer on $url within 10 s"; }
import sys, time, urllib.request
for _ in range(100):
    try:
        with urllib.request.urlopen(sys.argv[1], timeout=1) as r:
            if r.status == 200: sys.exit(0)
    except OSError:
        time.sleep(0.1)
sys.exit(1)
PYEOF
step "polylocd up (instance $instance), live view on $url"

node "$js/check_live_protocol.mjs" "ws://127.0.0.1:$port" --max-clients 4 > "$tmp/protocol.log" 2>&1 ||
  { show "check_live_protocol" "$tmp/protocol.log"; alive "during the protocol checks"; fail "protocol checks (above)"; }
alive "after the protocol checks"
step "protocol checks ok: $(grep -c '^(c)' "$tmp/protocol.log") malformed-message lines, limits and refusals as configured"

# The viewers of the run: Foxglove's client (ends when play has written the truth) and one that
# stops reading. Both subscribed before play starts.
node "$js/check_live_foxglove.mjs" "ws://127.0.0.1:$port" --until-file "$tmp/truth.tum" --stall-check \
  --timeout 240 --out "$tmp/foxglove.json" > "$tmp/foxglove.log" 2>&1 &
fox=$!; bg+=("$fox")
node "$js/stall_live_client.mjs" "ws://127.0.0.1:$port" --timeout 200 > "$tmp/stall.log" 2>&1 &
stall=$!; bg+=("$stall")
for _ in $(seq 150); do
  grep -q "subscribed to" "$tmp/foxglove.log" && grep -q "stopped reading" "$tmp/stall.log" && break
  { kill -0 "$fox" && kill -0 "$stall"; } 2>/dev/null || break
  sleep 0.1
done
grep -q "subscribed to" "$tmp/foxglove.log" || { show "check_live_foxglove" "$tmp/foxglove.log"; fail "the Foxglove client did not subscribe"; }
grep -q "stopped reading" "$tmp/stall.log" || { show "stall_live_client" "$tmp/stall.log"; fail "the stalling client did not subscribe"; }
step "Foxglove client and stalling client subscribed; play 20 s of the lab tour"

# The page, headless, connected before play starts (a browser starting on a loaded machine can
# take longer than the run); it waits for poses, then takes two shots 2 s apart.
node "$js/check_live_page.mjs" "$url" --shots 2 --interval-ms 2000 --out "$tmp/shots" --ready-file "$tmp/page.ready" \
  > "$tmp/page.log" 2>&1 &
page=$!; bg+=("$page")
for _ in $(seq 900); do  # 90 s
  [ -f "$tmp/page.ready" ] && break
  kill -0 "$page" 2>/dev/null || break
  sleep 0.1
done
[ -f "$tmp/page.ready" ] || { show "check_live_page" "$tmp/page.log"; fail "the page did not connect within 90 s"; }
step "page connected in headless Chromium"
play_rc=0
timeout 120 "$POLYLOC" play --scenario maps/scenarios/lab_tour.yaml --shm "$instance" --duration 20 --json --quiet \
  --truth "$tmp/truth.tum" > "$tmp/play.json" 2> "$tmp/play.err" || play_rc=$?
alive "during play (viewers attached)"
[ "$play_rc" = 0 ] || { show "polyloc play" "$tmp/play.err"; fail "polyloc play exited with $play_rc"; }
step "play done"

# Each client's verdict.
rc=0; wait "$stall" || rc=$?
[ "$rc" = 0 ] || { show "stall_live_client" "$tmp/stall.log"; show "polylocd log" "$tmp/polylocd.log" 20; fail "the stalling client was not cut off (exit $rc)"; }
step "$(grep "dropped by the server" "$tmp/stall.log")"
rc=0; wait "$page" || rc=$?
[ "$rc" = 0 ] || { show "check_live_page" "$tmp/page.log"; fail "page check failed (exit $rc)"; }
step "page: $(grep -c '^shot' "$tmp/page.log") shots ok; $(grep '^moved' "$tmp/page.log" || true)"
rc=0; wait "$fox" || rc=$?
cat "$tmp/foxglove.log"
[ "$rc" = 0 ] || fail "Foxglove client check failed (exit $rc; its FAIL lines above)"
bg=()
alive "after the clients ended"
# Exactly one viewer was cut off, the stalling one: in polylocd's log and in its health.
cuts=$(grep -c "disconnected: it took nothing" "$tmp/polylocd.log" || true)
slow=$("$PY" -c 'import json, sys; print(json.load(open(sys.argv[1]))["last_health_viewers"]["disconnected_slow"])' "$tmp/foxglove.json")
if [ "$cuts" != 1 ] || [ "$slow" != 1 ]; then
  fail "expected one viewer cut off (the stalling one): polylocd logged $cuts, its health counts disconnected_slow $slow"
fi

# What play saw (printed, not judged here: frames lost depend on the machine's load, and with
# chromium and three viewers beside polylocd on 2 cores a loaded CI machine starves it with or
# without them; what viewers cost polylocd is measured by bench/live_viewers.sh and guarded in
# docs/figures.json). Broken frames, though, never come from load.
"$PY" - "$tmp/play.json" <<'PYEOF' || fail "play summary (above)"
import json, sys
j = json.load(open(sys.argv[1]))
lost = j["dropped"] + j["rejected"]
print(f"live_view: play: {j['poses']} poses, latency p50 {j['latency_ms']['p50']:.1f} ms max {j['latency_ms']['max']:.0f} ms, "
      f"lost {lost} of {j['sent']} frames")
other = {ch: {k: e[k] for k in ("nan", "size", "future") if e[k]} for ch, e in j["polylocd"]["inputs"].items()}
assert not any(other.values()), ("frames rejected as broken", other)
assert j["poses"] > 50, ("poses", j["poses"])
PYEOF

kill -INT "$pid"
rc=0; wait "$pid" || rc=$?
pid=
[ "$rc" = 0 ] || { show "polylocd log" "$tmp/polylocd.log"; fail "polylocd exited with $rc on SIGINT"; }
grep -q "stopped after" "$tmp/polylocd.log" || { show "polylocd log" "$tmp/polylocd.log"; fail "polylocd did not log its stop"; }
for want in "live view on http://127.0.0.1:$port/" "live view: client .* connected" "live view: refused .*max_clients" \
            "live view: client .* disconnected: it took nothing"; do
  grep -q "$want" "$tmp/polylocd.log" || { show "polylocd log" "$tmp/polylocd.log"; fail "polylocd's log has no line matching '$want'"; }
done
if grep -q "live view stopped" "$tmp/polylocd.log"; then show "polylocd log" "$tmp/polylocd.log"; fail "the live view server stopped with an error"; fi
step "polylocd stopped on SIGINT: $(grep -c 'live view' "$tmp/polylocd.log") live view lines in its log"
echo "live_view: ok (${SECONDS} s)"
