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

source "$(dirname "$0")/lib.sh"
url+='&recv_buf_size=4194304'

start_logger run.lcmlog
start complement "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
# shellcheck disable=SC2034  # complement, pilot: used as ${!name} below
complement=$!
start pilot "$bin/lasonic-pilot" --config "$config" --lcm-url "$url"
# shellcheck disable=SC2034
pilot=$!

# Waits for both heartbeats, publishes, waits until both report every message received.
"$bin/lasonic-bad-messages" feed "$url" >"$tmp/feed.out" 2>"$tmp/feed.err" || die "feed: $(cat "$tmp/feed.err")"
cat "$tmp/feed.out"

for name in complement pilot; do
  p=${!name}
  kill -0 "$p" 2>/dev/null || die "lasonic-$name died on bad messages"
  expect_term_exit "$p" "lasonic-$name:"
done
sleep 0.3  # the final PROCESS_STATUS reaches the logger
stop_logger

"$bin/lasonic-bad-messages" check "$tmp/run.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
  cat "$tmp/check.out"
  die "log check: $(cat "$tmp/check.err")"
}
grep -E '^(lasonic-[a-z]+\.(errors|last_error)|valid\.|last\.)' "$tmp/check.out"
echo "$test_name: PASS"
