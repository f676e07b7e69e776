#!/usr/bin/env bash
# complement.sh: integration test of lasonic-complement over real LCM. Run it inside a private
# network namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
#  1. a bad config exits 2 naming the key;
#  2. the process, fed the paper's Fig. 4 fixture (lasonic-complement-check publish), publishes
#     RADAR_MAP, SONAR_HYPOTHESIS and SONAR_COMPLEMENT with the expected classes and counts them
#     (and the rejected NaN) in PROCESS_STATUS; it keeps running and exits 0 on SIGTERM.
set -euo pipefail

source "$(dirname "$0")/lib.sh"

# 1. Config errors name the key and exit 2.
printf 'complement:\n  tolerence: 0.2\n' >"$tmp/bad.yaml"
expect_bad_config complement.tolerence complement.tolerence "$bin/lasonic-complement" --config "$tmp/bad.yaml"

# 2. A live run with the shipped configuration.
start_logger run.lcmlog
start complement "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
proc=$!
wait_ready complement
"$bin/lasonic-complement-check" publish "$url" || die "publishing the fixture failed"
sleep 1.5  # at least one heartbeat after the input
kill -0 "$proc" 2>/dev/null || die "lasonic-complement died"
expect_term_exit "$proc"
sleep 0.3
stop_logger

"$bin/lasonic-complement-check" log "$tmp/run.lcmlog" 2>"$tmp/check.err" || die "$(cat "$tmp/check.err")"
echo "$test_name: PASS"
