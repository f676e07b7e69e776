#!/usr/bin/env bash
# sim_bad_input.sh: bad input to the simulator executables. Run it inside a private network
# namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE
# (repository root).
#  1. lasonic-sim, lasonic-sim-world, lasonic-laser-driver and lasonic-sonar-driver, given a
#     missing scenario file, a scenario with a YAML syntax error, a scenario with an unknown key,
#     a missing config file, or a config with a bad value: exit status 2 and one message that
#     names the file and, for a bad key, the key path;
#     lasonic-sim --check-config says a usable set-up is usable (exit 0, nothing written) and a
#     bad one is not (exit 2 naming the key); without it, --out is required (exit 2);
#  2. lasonic-laser-driver fed malformed messages on SIM_STATE (lasonic-sonar-check garbage:
#     19 bytes that are no lasonic type): counts them as decode errors in PROCESS_STATUS, keeps
#     running, and still scans when good SIM_STATE messages follow. (lasonic-sonar-driver gets
#     the same in sonar_driver.sh; lasonic-sim-world subscribes to nothing.)
set -euo pipefail

source "$(dirname "$0")/lib.sh"

# 1. Start-up errors.
printf 'name: x\nduration_s: 5\nseed: 1\nobstacles: [\n' >"$tmp/syntax.yaml"
sed 's/^  speed: 0.3$/  speed: 0.3\n  colour: red/' "$scenario" >"$tmp/unknown_key.yaml"
grep -q colour "$tmp/unknown_key.yaml" || die "could not make unknown_key.yaml"
printf 'sonar:\n  range_min: 5\n' >"$tmp/bad_sonar.yaml"
printf 'laser:\n  readings: 1\n' >"$tmp/bad_laser.yaml"
printf 'odometry:\n  rate_hz: -1\n' >"$tmp/bad_odometry.yaml"
printf 'sonar:\n  profile: realistic\n' >"$tmp/bad_profile.yaml"
printf 'laser:\n  profile: perfect\n' >"$tmp/bad_laser_profile.yaml"
# A scenario whose material has a bad physical parameter, and one with a bad beam_scale.
sed 's/^obstacles:$/materials:\n  metal: {sonar_roughness_mm: -2}\nobstacles:/' "$scenario" >"$tmp/bad_material.yaml"
grep -q sonar_roughness_mm "$tmp/bad_material.yaml" || die "could not make bad_material.yaml"
printf 'sonar: {beam_scale: -0.8}\n' | cat "$scenario" - >"$tmp/bad_beam_scale.yaml"

expect_error() {  # TOOL CASE WANT ARGS...: exit status 2 and stderr+stdout contain WANT
  local tool=$1 case=$2 want=$3 rc=0
  shift 3
  local extra=(--lcm-url "$url")
  [[ $tool == lasonic-sim ]] && extra=(--out "$tmp/out.lcmlog")
  timeout 20 "$bin/$tool" "$@" "${extra[@]}" >"$tmp/$tool.$case.out" 2>&1 || rc=$?
  [[ $rc -eq 2 ]] || die "$tool ($case): exit status $rc, expected 2: $(tail -n 3 "$tmp/$tool.$case.out")"
  grep -qF -- "$want" "$tmp/$tool.$case.out" ||
    die "$tool ($case): the message does not say '$want': $(tail -n 3 "$tmp/$tool.$case.out")"
  echo "  $tool ($case): $(grep -F -- "$want" "$tmp/$tool.$case.out" | head -n 1 | sed 's/^\[[^]]*\] //')"
}
declare -A bad_file=(
  [lasonic-sim]=bad_sonar [lasonic-sim-world]=bad_odometry
  [lasonic-laser-driver]=bad_laser [lasonic-sonar-driver]=bad_sonar
)
declare -A bad_value=(
  [bad_sonar]='sonar.range_min: range_min (5) must be < range_max ('
  [bad_odometry]='odometry.rate_hz: must be in [1, 1000]'
  [bad_laser]='laser.readings: must be in [2, 100000]'
)
for tool in lasonic-sim lasonic-sim-world lasonic-laser-driver lasonic-sonar-driver; do
  [[ -x $bin/$tool ]] || die "$bin/$tool was not built"
  expect_error "$tool" missing_scenario "$tmp/nonexistent.yaml: cannot open file" --scenario "$tmp/nonexistent.yaml"
  expect_error "$tool" yaml_syntax "syntax.yaml: YAML syntax error at line" --scenario "$tmp/syntax.yaml"
  expect_error "$tool" unknown_key "unknown_key.yaml: robot.colour: unknown key" --scenario "$tmp/unknown_key.yaml"
  expect_error "$tool" missing_config "$tmp/nonexistent-config.yaml: cannot open file" \
    --scenario "$scenario" --config "$tmp/nonexistent-config.yaml"
  f=${bad_file[$tool]}
  expect_error "$tool" bad_config "$f.yaml: ${bad_value[$f]}" --scenario "$scenario" --config "$tmp/$f.yaml"
  expect_error "$tool" bad_material "bad_material.yaml: materials.metal.sonar_roughness_mm: must be in [0, 1000]" \
    --scenario "$tmp/bad_material.yaml"
done
expect_error lasonic-sim bad_profile "bad_profile.yaml: sonar.profile: must be one of physical, ideal" \
  --scenario "$scenario" --config "$tmp/bad_profile.yaml"
expect_error lasonic-laser-driver bad_profile "bad_laser_profile.yaml: laser.profile: must be one of physical, ideal" \
  --scenario "$scenario" --config "$tmp/bad_laser_profile.yaml"
expect_error lasonic-sonar-driver bad_beam_scale "bad_beam_scale.yaml: sonar.beam_scale: must be in (0, 5]" \
  --scenario "$tmp/bad_beam_scale.yaml"
expect_error lasonic-sim bad_beam_scale "bad_beam_scale.yaml: sonar.beam_scale: must be in (0, 5]" \
  --scenario "$tmp/bad_beam_scale.yaml"
expect_error lasonic-sim bad_robot_speed "--robot-speed must be in (0, 5] m/s" --scenario "$scenario" --robot-speed 0
# lasonic-sim --check-config: the same checks, writing nothing; without it --out is required.
rc=0
"$bin/lasonic-sim" --scenario "$scenario" --config "$config" --seed 3 --check-config >"$tmp/check.out" 2>&1 || rc=$?
[[ $rc -eq 0 ]] || die "lasonic-sim --check-config on a usable set-up: exit $rc: $(cat "$tmp/check.out")"
grep -qF "lasonic-sim: configuration usable $config, scenario $scenario:" "$tmp/check.out" ||
  die "lasonic-sim --check-config did not say the set-up is usable: $(cat "$tmp/check.out")"
grep -qF "seed 3, laser physical, sonar physical" "$tmp/check.out" ||
  die "lasonic-sim --check-config did not say what it would simulate: $(cat "$tmp/check.out")"
echo "  lasonic-sim (check_config): $(cat "$tmp/check.out")"
rc=0
"$bin/lasonic-sim" --scenario "$scenario" --config "$tmp/bad_sonar.yaml" --check-config >"$tmp/check_bad.out" 2>&1 ||
  rc=$?
[[ $rc -eq 2 ]] && grep -qF "bad_sonar.yaml: ${bad_value[bad_sonar]}" "$tmp/check_bad.out" ||
  die "lasonic-sim --check-config on a bad config: exit $rc, expected 2 naming the key: $(cat "$tmp/check_bad.out")"
echo "  lasonic-sim (check_config, bad config): $(cat "$tmp/check_bad.out")"
rc=0
"$bin/lasonic-sim" --scenario "$scenario" >"$tmp/no_out.out" 2>&1 || rc=$?
[[ $rc -eq 2 ]] && grep -qF "lasonic-sim: --out is required" "$tmp/no_out.out" ||
  die "lasonic-sim without --out: exit $rc, expected 2: $(cat "$tmp/no_out.out")"
echo "  lasonic-sim (no --out): $(cat "$tmp/no_out.out")"
echo "$test_name: (1) ok: every start-up error exits 2 and names the file and key"

# 2. Malformed messages on the laser driver's input.
start_logger run.lcmlog
start driver "$bin/lasonic-laser-driver" --config "$config" --scenario "$scenario" --lcm-url "$url"
driver=$!
wait_ready driver
"$bin/lasonic-sonar-check" garbage "$url" SIM_STATE 5 || die "could not publish garbage"
sleep 0.5
kill -0 "$driver" 2>/dev/null || die "the laser driver died on malformed SIM_STATE messages"
"$bin/lasonic-sim-world" --scenario "$scenario" --duration 1 --lcm-url "$url" 2>"$tmp/world.err" >&2 ||
  die "lasonic-sim-world failed"
sleep 1.5  # at least one heartbeat after the run
kill -0 "$driver" 2>/dev/null || die "the laser driver died during the run"
expect_term_exit "$driver" "laser driver"
stop_logger
"$bin/lasonic-log-stats" "$tmp/run.lcmlog" >"$tmp/stats" 2>"$tmp/stats.err" || die "log-stats: $(cat "$tmp/stats.err")"
grep '^lasonic-laser-driver\.' "$tmp/stats" || true
decode=$(stat lasonic-laser-driver.decode_errors.SIM_STATE)
if [[ -z $decode ]] || ((decode < 5)); then
  die "lasonic-laser-driver counted ${decode:-no} decode errors on SIM_STATE, expected 5"
fi
(($(stat LASER_SCAN) >= 4)) || die "only $(stat LASER_SCAN) LASER_SCAN after the malformed messages, expected 5"
echo "$test_name: (2) ok: $decode malformed SIM_STATE messages counted; $(stat LASER_SCAN) scans after them"
echo "$test_name: PASS"
