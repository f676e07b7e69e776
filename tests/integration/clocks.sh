#!/usr/bin/env bash
# clocks.sh: sensor drivers whose computers' clocks disagree with the odometry's, live over real
# LCM (README "Clocks"). Run it inside a private network namespace (tests/netns/in-netns.sh;
# ctest does). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  1. one clock (the shipped configuration): lasonic-complement reports no time.* finding;
#  2. the laser's clock 100 ms ahead and the sonar's 100 ms behind (the simulator's
#     laser.clock_offset_s and sonar.clock_offset_s): lasonic-complement reports both, names them
#     in its last error, keeps running and exits 0 on SIGTERM.
set -euo pipefail

source "$(dirname "$0")/lib.sh"

# run NAME SECONDS [DRIVER_OVERLAY]: world, both drivers (with the overlay) and the complement,
# recorded into $tmp/NAME.lcmlog; the stats of the log into $tmp/stats.
run() {
  local name=$1 seconds=$2 overlay=${3:-}
  local -a extra=()
  [[ -n $overlay ]] && extra=(--config "$overlay")
  start_logger "$name.lcmlog" "$name-logger.err"
  start "$name-complement" "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
  local complement=$!
  start "$name-laser" "$bin/lasonic-laser-driver" --config "$config" "${extra[@]}" --scenario "$scenario" --lcm-url "$url"
  local laser=$!
  start "$name-sonar" "$bin/lasonic-sonar-driver" --config "$config" "${extra[@]}" --scenario "$scenario" --lcm-url "$url"
  local sonar=$!
  wait_ready "$name-complement"
  wait_ready "$name-laser"
  wait_ready "$name-sonar"
  "$bin/lasonic-sim-world" --config "$config" --scenario "$scenario" --duration "$seconds" --lcm-url "$url" \
    2>"$tmp/$name-world.err" >&2 || die "lasonic-sim-world failed"
  sleep 1.3  # a heartbeat after the last input
  kill -0 "$complement" 2>/dev/null || die "lasonic-complement died ($name)"
  expect_term_exit "$complement" "complement ($name)"
  kill "$laser" "$sonar" 2>/dev/null || true
  sleep 0.3
  stop_logger
  "$bin/lasonic-log-stats" "$tmp/$name.lcmlog" >"$tmp/stats" 2>"$tmp/stats.err" || die "log-stats: $(cat "$tmp/stats.err")"
}
count() { local v; v=$(stat "lasonic-complement.$1"); echo "${v:-0}"; }

# 1. One clock.
run synced 6
[[ $(stat LASER_SCAN) -ge 20 ]] || die "only $(stat LASER_SCAN) scans in the synced run"
for k in laser_ahead_of_odometry laser_behind_odometry sonar_ahead_of_odometry sonar_behind_odometry; do
  [[ $(count "time.$k") -eq 0 ]] || die "one clock, yet time.$k = $(count "time.$k")"
done

# 2. Two computers' clocks off by 100 ms, either way.
printf 'laser:\n  clock_offset_s: 0.1\nsonar:\n  clock_offset_s: -0.1\n' >"$tmp/skew.yaml"
run skewed 6 "$tmp/skew.yaml"
[[ $(count time.laser_ahead_of_odometry) -ge 1 ]] || die "the laser's clock 100 ms ahead was not reported"
[[ $(count time.sonar_behind_odometry) -ge 1 ]] || die "the sonar's clock 100 ms behind was not reported"
[[ $(count time.laser_behind_odometry) -eq 0 ]] || die "the laser ahead was also reported behind"
[[ $(count time.sonar_ahead_of_odometry) -eq 0 ]] || die "the sonar behind was also reported ahead"
[[ $(stat LASER_SCAN) -ge 20 ]] || die "only $(stat LASER_SCAN) scans in the skewed run"
grep -q "ahead of the odometry" "$tmp/skewed-complement.err" ||
  die "the complement's log does not say the laser's clock runs ahead: $(tail -3 "$tmp/skewed-complement.err")"
echo "$test_name: PASS"
