#!/usr/bin/env bash
# sonar_driver.sh: integration test of lasonic-sonar-driver over real LCM. Run it inside a private
# network namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
#  1. bad config -> exit 2 naming the key;
#  2. the driver, fed garbage on SIM_STATE and then 3 s of fig7_lab by lasonic-sim-world,
#     publishes SONAR_RING / SONAR_TRUTH / SONAR_GEOMETRY at their rates, consistent with each
#     other (lasonic-sonar-check), counts the decode errors in PROCESS_STATUS and keeps running;
#  3. a second world run (sim time starting over, i.e. going back more than 1 s) is a restarted
#     clock: the driver counts one time reset, starts afresh and fires for the second run too;
#     it keeps running and exits cleanly on SIGTERM.
set -euo pipefail

source "$(dirname "$0")/lib.sh"

# 1. Config errors name the key and exit 2.
printf 'sonar:\n  ring: {count: 24, beams: 3}\n' >"$tmp/bad.yaml"
expect_bad_config 'sonar.ring.beams: unknown key' sonar.ring.beams \
  "$bin/lasonic-sonar-driver" --config "$tmp/bad.yaml" --scenario "$scenario"

# 2. A live run, recorded by start_recorder (lib.sh: a queue of 100 000 messages): SONAR_TRUTH
# must count exactly as SONAR_RING, which a logger dropping part of a burst would break.
start_recorder recorder run.lcmlog
start driver "$bin/lasonic-sonar-driver" --config "$config" --scenario "$scenario" --lcm-url "$url"
driver=$!
wait_ready driver recorder

"$bin/lasonic-sonar-check" garbage "$url" SIM_STATE 5
"$bin/lasonic-sim-world" --scenario "$scenario" --duration 3 --lcm-url "$url" 2>"$tmp/world.err" >&2 ||
  die "lasonic-sim-world failed"
sleep 1.5  # at least one heartbeat after the run
kill -0 "$driver" 2>/dev/null || die "the driver died during the run"

# 3. Sim time starting over: every state goes back in time.
"$bin/lasonic-sim-world" --scenario "$scenario" --duration 0.5 --lcm-url "$url" 2>"$tmp/world2.err" >&2 ||
  die "second lasonic-sim-world failed"
sleep 1.5
kill -0 "$driver" 2>/dev/null || die "the driver died on states going back in time"
expect_term_exit "$driver" driver
sleep 0.3
stop_recorder

"$bin/lasonic-sonar-check" log "$tmp/run.lcmlog" >"$tmp/stats" 2>"$tmp/check.err" || die "log check: $(cat "$tmp/check.err")"
cat "$tmp/stats"

# 3 s + 0.5 s of sim time, a group every 30 ms: ~117 firings of 4 readings; geometry at 1 Hz.
rings=$(stat SONAR_RING)
((rings >= 95 && rings <= 122)) || die "SONAR_RING count $rings, expected about 117"
[[ $(stat SONAR_TRUTH) -eq $rings ]] || die "SONAR_TRUTH count $(stat SONAR_TRUTH) != SONAR_RING count $rings"
[[ $(stat readings) -eq $((4 * rings)) ]] || die "$(stat readings) readings in $rings firings, expected 4 each"
geometry=$(stat SONAR_GEOMETRY)
((geometry >= 4 && geometry <= 5)) || die "SONAR_GEOMETRY count $geometry, expected 4..5 (1 Hz, and on restart)"
(($(stat driver.decode_errors.SIM_STATE) >= 1)) || die "garbage on SIM_STATE not counted as decode errors"
[[ $(stat driver.time_resets) == 1 ]] || die "the restarted world: time_resets = $(stat driver.time_resets), expected 1"
echo "$test_name: PASS"
