#!/usr/bin/env bash
# sim_laser.sh: integration test of lasonic-sim-world and lasonic-laser-driver over real LCM.
# Run it inside a private network namespace (tests/netns/in-netns.sh; ctest does).
# Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  1. bad config or scenario -> exit 2 with a message naming the key;
#  2. the world (3 s of fig7_lab) and the laser driver publish SIM_STATE, ODOMETRY and
#     LASER_SCAN at their rates; the world exits 0 by itself;
#  3. a second world run (sim time starting over, i.e. going back more than 1 s) is a restarted
#     clock: the driver counts one time reset, rejects nothing, scans the second run, keeps
#     running and exits 0 on SIGTERM.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
# within VALUE LO HI: LO <= VALUE <= HI (decimals allowed)
within() { awk -v v="$1" -v lo="$2" -v hi="$3" 'BEGIN {exit !(v != "" && v >= lo && v <= hi)}'; }

# 1. Start-up errors: exit 2, and the message names the file's key.
printf 'laser:\n  fov_deg: 400\n' >"$tmp/bad_laser.yaml"
expect_config_error laser_fov 'bad_laser.yaml: laser.fov_deg: must be in [1, 360]' \
  "$bin/lasonic-laser-driver" --config "$tmp/bad_laser.yaml" --scenario "$scenario"
printf 'odometry:\n  rate: 50\n' >"$tmp/bad_odometry.yaml"
expect_config_error odometry_key 'bad_odometry.yaml: odometry.rate: unknown key' \
  "$bin/lasonic-sim-world" --config "$tmp/bad_odometry.yaml" --scenario "$scenario"
sed 's/radius: 0.01}/radius: 0}/' "$scenario" >"$tmp/bad_scenario.yaml"
expect_config_error scenario_radius 'bad_scenario.yaml: obstacles[2].radius: must be > 0' \
  "$bin/lasonic-sim-world" --scenario "$tmp/bad_scenario.yaml"
expect_config_error scenario_laser 'bad_scenario.yaml: obstacles[2].radius: must be > 0' \
  "$bin/lasonic-laser-driver" --scenario "$tmp/bad_scenario.yaml"

# 2. A live run, recorded. The counts below are checked against tight bounds, so the run is
# recorded by start_recorder (lib.sh: a queue of 100 000 messages), not by lcm-logger, whose
# short queue may drop part of a burst on a loaded machine.
start_recorder recorder run.lcmlog
start driver "$bin/lasonic-laser-driver" --config "$config" --scenario "$scenario" --lcm-url "$url"
driver=$!
wait_ready driver recorder
"$bin/lasonic-sim-world" --config "$config" --scenario "$scenario" --duration 3 --lcm-url "$url" \
  2>"$tmp/world.err" >&2 || die "lasonic-sim-world failed"
sleep 0.3
stop_recorder
kill -0 "$driver" 2>/dev/null || die "the laser driver died during the run"

"$bin/lasonic-log-stats" "$tmp/run.lcmlog" >"$tmp/stats" 2>"$tmp/stats.err" || die "log-stats: $(cat "$tmp/stats.err")"
cat "$tmp/stats"
# 3 s at 50 Hz: 151 states (t = 0 .. 3 s); a scan every 0.2 s, the first complete at t = 0.2 s.
within "$(stat SIM_STATE)" 148 151 || die "SIM_STATE count $(stat SIM_STATE), expected 151"
within "$(stat ODOMETRY)" 148 151 || die "ODOMETRY count $(stat ODOMETRY), expected 151"
within "$(stat SIM_STATE.rate_hz)" 45 55 || die "SIM_STATE rate $(stat SIM_STATE.rate_hz) Hz, expected 50"
within "$(stat ODOMETRY.rate_hz)" 45 55 || die "ODOMETRY rate $(stat ODOMETRY.rate_hz) Hz, expected 50"
within "$(stat LASER_SCAN)" 14 15 || die "LASER_SCAN count $(stat LASER_SCAN), expected 15"
within "$(stat LASER_SCAN.rate_hz)" 4.5 5.5 || die "LASER_SCAN rate $(stat LASER_SCAN.rate_hz) Hz, expected 5"
[[ $(stat LASER_SCAN.readings) -eq 720 ]] || die "$(stat LASER_SCAN.readings) readings per scan, expected 720"
# A closed metal room: every ray returns, except where the black box absorbs it.
within "$(stat LASER_SCAN.ok_fraction)" 0.9 1.0 || die "only $(stat LASER_SCAN.ok_fraction) of the readings returned"
[[ $(stat lasonic-sim-world.errors) -eq 0 ]] || die "lasonic-sim-world reported errors"
[[ $(stat lasonic-laser-driver.errors) -eq 0 ]] || die "lasonic-laser-driver reported errors"

# 3. Sim time starting over: the driver starts afresh.
start_recorder recorder2 restart.lcmlog
wait_ready recorder2
"$bin/lasonic-sim-world" --scenario "$scenario" --duration 0.5 --lcm-url "$url" 2>"$tmp/world2.err" >&2 ||
  die "second lasonic-sim-world failed"
sleep 0.3
kill -0 "$driver" 2>/dev/null || die "the laser driver died on states going back in time"
expect_term_exit "$driver" "laser driver"
sleep 0.3
stop_recorder
"$bin/lasonic-log-stats" "$tmp/restart.lcmlog" >"$tmp/stats" 2>"$tmp/stats.err" || die "log-stats: $(cat "$tmp/stats.err")"
[[ $(stat lasonic-laser-driver.time_resets) == 1 ]] ||
  die "time_resets = $(stat lasonic-laser-driver.time_resets), expected 1 (the second run)"
[[ -z $(stat lasonic-laser-driver.rejected.sim_state) ]] || die "states of the second run were rejected"
within "$(stat LASER_SCAN)" 1 3 || die "$(stat LASER_SCAN) scans from the second run (0.5 s), expected 1..3"
echo "$test_name: PASS"
