#!/usr/bin/env bash
# bad_messages.sh: malformed and semantically bad MESSAGES to the pipeline processes. Run it inside
# a private network namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
# lasonic-complement and lasonic-pilot (shipped config) are fed by lasonic-bad-messages: random
# bytes, truncated messages and messages of the wrong type on every channel they subscribe to;
# NaN / negative / huge values, out-of-range sensor ids and classes, time going backwards; then a
# short valid stream. From the lcm-logger log: every bad input is counted under its counter
# (decode_errors.<CHANNEL>, rejected.*) and nothing else, last_error names the field, the valid
# stream still yields RADAR_MAP / SONAR_COMPLEMENT / SECTOR_MAP with finite values; both
# processes keep running and exit 0 on SIGTERM.
set -euo pipefail

bin=${LASONIC_BIN:?set LASONIC_BIN}
src=${LASONIC_SOURCE:?set LASONIC_SOURCE}
url='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
config=$src/deploy/config/lasonic.yaml
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
die() {
  echo "bad_messages.sh: FAIL: $*" >&2
  for f in "$tmp"/*.err; do [[ -f $f ]] && { echo "--- $f" >&2; tail -20 "$f" >&2; }; done
  exit 1
}

lcm-logger --lcm-url="$url" "$tmp/run.lcmlog" >"$tmp/logger.err" 2>&1 &
logger=$!
pids+=("$logger")
"$bin/lasonic-complement" --config "$config" --lcm-url "$url" 2>"$tmp/complement.err" >&2 &
complement=$!
pids+=("$complement")
"$bin/lasonic-pilot" --config "$config" --lcm-url "$url" 2>"$tmp/pilot.err" >&2 &
pilot=$!
pids+=("$pilot")

# Waits for both heartbeats, publishes, waits until both report every message received.
"$bin/lasonic-bad-messages" feed "$url" >"$tmp/feed.out" 2>"$tmp/feed.err" || die "feed: $(cat "$tmp/feed.err")"
cat "$tmp/feed.out"

for name in complement pilot; do
  p=${!name}
  kill -0 "$p" 2>/dev/null || die "lasonic-$name died on bad messages"
  kill -TERM "$p"
  rc=0
  wait "$p" || rc=$?
  [[ $rc -eq 0 ]] || die "lasonic-$name: exit status $rc after SIGTERM, expected 0"
done
sleep 0.3  # the final PROCESS_STATUS reaches the logger
kill -INT "$logger"
wait "$logger" || true

"$bin/lasonic-bad-messages" check "$tmp/run.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
  cat "$tmp/check.out"
  die "log check: $(cat "$tmp/check.err")"
}
grep -E '^(lasonic-[a-z]+\.(errors|last_error)|valid\.|last\.)' "$tmp/check.out"
echo "bad_messages.sh: PASS"
