#!/usr/bin/env bash
# navigator.sh: integration test of lasonic-navigator over real LCM. Run it inside a private
# network namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
#  1. --help works; a bad config exits 2 naming the key; the shipped config starts cleanly;
#  2. lasonic-complement, lasonic-pilot and lasonic-navigator run live while lcm-logplayer plays a
#     5 s lasonic-sim log of fig7_lab into them and a recorder takes every channel: AGM_TACTICAL,
#     AGM_LINES and CURRENT_SENSOR_MAP come at the navigator's 2 Hz (of message time, so also of
#     wall time here), independent of the pilot's SECTOR_MAP (one per firing group and scan); the
#     navigator's PROCESS_STATUS shows its AGM cycles and no errors; it exits 0 on SIGTERM;
#  3. with the navigator killed (SIGKILL), the same log played again into a fresh complement and
#     pilot: the pilot's SECTOR_MAP count is unchanged (nothing but LCM connects the two levels),
#     counting the maps its sensor messages made (a loaded machine adds maps on ODOMETRY);
#  4. a glass wall driven past face-on, played into a fresh complement and navigator: the
#     navigator takes laser glints from LASER_SCAN (PROCESS_STATUS agm.laser_glints and
#     agm.laser_glint_hits) and matches the scans (scan_match.matched, scan_match.keyframes),
#     and does neither with both turned off.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
url+='&recv_buf_size=4194304'
command -v lcm-logplayer >/dev/null 2>&1 || { echo "$test_name: SKIP: lcm-logplayer not found (liblcm-bin)"; exit 77; }

# 1. Command line and configuration.
"$bin/lasonic-navigator" --help >"$tmp/help.out" || die "--help failed"
grep -q -- '--lcm-url' "$tmp/help.out" || die "--help does not mention --lcm-url"
printf 'navigator:\n  agm: {t: -1}\n' >"$tmp/bad.yaml"
expect_bad_config navigator.agm.t navigator.agm.t "$bin/lasonic-navigator" --config "$tmp/bad.yaml"
printf 'navigator:\n  lines: {max_gap: 0}\n' >"$tmp/bad.yaml"
expect_bad_config navigator.lines.max_gap navigator.lines.max_gap "$bin/lasonic-navigator" --config "$tmp/bad.yaml"
rc=0
timeout --preserve-status -s TERM 1 "$bin/lasonic-navigator" --config "$config" \
  --lcm-url "$url" 2>"$tmp/shipped.err" >&2 || rc=$?
[[ $rc -eq 0 ]] || die "the shipped config: exit status $rc, expected 0 after SIGTERM"

# Steps 2 and 3 count messages, so they record with start_recorder (lib.sh: a queue of
# 100 000), not lcm-logger, which queues 30 and drops the rest of a burst on a loaded machine
# (README "Recording and replaying"): the counts would test the logger's queue.
[[ -x $bin/lasonic-fault-check ]] || die "$bin/lasonic-fault-check was not built"

# 2. Live: complement, pilot, navigator; a 5 s log played in.
"$bin/lasonic-sim" --scenario "$scenario" --config "$config" --duration 5 --out "$tmp/raw.lcmlog" >/dev/null ||
  die "lasonic-sim failed"
start complement "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
complement=$!
start pilot "$bin/lasonic-pilot" --config "$config" --lcm-url "$url"
pilot=$!
start navigator "$bin/lasonic-navigator" --config "$config" --lcm-url "$url"
navigator=$!
start_recorder recorder1 run1.lcmlog
wait_ready complement pilot navigator recorder1
play_log 30 "$tmp/raw.lcmlog"
sleep 1.5  # the last outputs and a heartbeat
kill -0 "$navigator" 2>/dev/null || die "the navigator died during the run"
stop_recorder
"$bin/lasonic-log-stats" "$tmp/run1.lcmlog" >"$tmp/stats" || die "cannot read the log"
cat "$tmp/stats" >"$tmp/run1.stats"
for ch in AGM_TACTICAL AGM_LINES CURRENT_SENSOR_MAP SECTOR_MAP; do
  [[ -n $(stat "$ch") ]] || die "no $ch in the log"
done
# 5 s of message time at 2 Hz: 10 (+1 for the first cycle); the pilot: ~38 per second.
for ch in AGM_TACTICAL AGM_LINES CURRENT_SENSOR_MAP; do
  n=$(stat "$ch")
  ((n >= 9 && n <= 12)) || die "$n $ch messages in 5 s, expected 10-11 (2 Hz)"
done
sectors=$(stat SECTOR_MAP)
((sectors >= 150)) || die "only $sectors SECTOR_MAP messages in 5 s"
# The pilot publishes one map per firing group and scan, and one on ODOMETRY when no sensor
# message made one for 0.1 s of message time: on a loaded machine a sensor message that reaches
# it late adds such a map (its PROCESS_STATUS counts them, sector_map.on_odometry). So the maps
# the sensors made are compared below, not the total.
on_odometry=$(stat lasonic-pilot.sector_map.on_odometry)
on_odometry=${on_odometry:-0}
cycles=$(stat lasonic-navigator.agm.cycles)
[[ -n $cycles ]] || die "no PROCESS_STATUS of lasonic-navigator with agm.cycles"
((cycles >= 135)) || die "the navigator ran only $cycles AGM cycles for ~147 firing groups (30 ms + 0-8 ms each)"
[[ $(stat lasonic-navigator.errors) == 0 ]] || die "the navigator reported $(stat lasonic-navigator.errors) errors"
echo "$test_name: (2) ok: AGM_TACTICAL $(stat AGM_TACTICAL), CURRENT_SENSOR_MAP $(stat CURRENT_SENSOR_MAP), SECTOR_MAP $sectors, navigator cycles $cycles"

# 3. The navigator killed: the pilot's output is the same. Fresh complement and pilot (the old
# ones would reject the log's times as going backwards).
kill -KILL "$navigator"
wait "$navigator" 2>/dev/null || true
expect_term_exit "$complement" lasonic-complement
expect_term_exit "$pilot" lasonic-pilot
start complement2 "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
complement2=$!
start pilot2 "$bin/lasonic-pilot" --config "$config" --lcm-url "$url"
pilot2=$!
start_recorder recorder2 run2.lcmlog
wait_ready complement2 pilot2 recorder2
play_log 30 "$tmp/raw.lcmlog"
sleep 1.5
stop_recorder
"$bin/lasonic-log-stats" "$tmp/run2.lcmlog" >"$tmp/stats" || die "cannot read the second log"
[[ -z $(stat AGM_TACTICAL) ]] || die "AGM_TACTICAL after the navigator was killed"
sectors2=$(stat SECTOR_MAP)
on_odometry2=$(stat lasonic-pilot.sector_map.on_odometry)
on_odometry2=${on_odometry2:-0}
made=$((sectors - on_odometry)) made2=$((sectors2 - on_odometry2))
((made2 >= made - 2 && made2 <= made + 2)) ||
  die "SECTOR_MAP: $made2 made by the sensors without the navigator ($sectors2 in all), $made with it ($sectors)"
echo "$test_name: (3) ok: SECTOR_MAP made by the sensors $made2 without the navigator, $made with it" \
  "(in all $sectors2 and $sectors; on ODOMETRY $on_odometry2 and $on_odometry)"

# 4. Laser glints over LCM: a glass wall 2.5 m beside a straight path, 6 s at 0.4 m/s.
expect_term_exit "$complement2" lasonic-complement
expect_term_exit "$pilot2" lasonic-pilot
cat >"$tmp/glass.yaml" <<'YAML'
name: glass_wall
duration_s: 6
seed: 2
obstacles:
  - {shape: segment, material: glass, from: [-1.0, 2.5], to: [5.0, 2.5]}
  - {shape: segment, material: wall, from: [-1.0, 4.5], to: [5.0, 4.5]}
  - {shape: segment, material: wall, from: [-1.0, -1.5], to: [5.0, -1.5]}
robot: {radius: 0.35, path: [[0.0, 0.0], [3.0, 0.0]], speed: 0.4}
YAML
"$bin/lasonic-sim" --scenario "$tmp/glass.yaml" --config "$config" --out "$tmp/glass.lcmlog" >/dev/null ||
  die "lasonic-sim (glass wall) failed"
printf 'navigator:\n  laser_glints: {max_incidence_deg: 0}\n  scan_matching: {enabled: false}\n' >"$tmp/no_glints.yaml"
for variant in shipped off; do
  extra=()
  [[ $variant == off ]] && extra=(--config "$tmp/no_glints.yaml")
  start "complement_$variant" "$bin/lasonic-complement" --config "$config" --lcm-url "$url"
  c=$!
  start "navigator_$variant" "$bin/lasonic-navigator" --config "$config" "${extra[@]}" --lcm-url "$url"
  n=$!
  start_logger "glass_$variant.lcmlog" "logger_glass_$variant.err"
  wait_ready "complement_$variant" "navigator_$variant"
  play_log 30 "$tmp/glass.lcmlog"
  sleep 1.5
  stop_logger
  expect_term_exit "$n" lasonic-navigator
  expect_term_exit "$c" lasonic-complement
  "$bin/lasonic-log-stats" "$tmp/glass_$variant.lcmlog" >"$tmp/stats" || die "cannot read the glass log"
  glints=$(stat lasonic-navigator.agm.laser_glints)
  hits=$(stat lasonic-navigator.agm.laser_glint_hits)
  matched=$(stat lasonic-navigator.scan_match.matched)
  keyframes=$(stat lasonic-navigator.scan_match.keyframes)
  if [[ $variant == shipped ]]; then
    ((${glints:-0} >= 5 && ${hits:-0} >= 20)) ||
      die "glass wall: ${glints:-no} laser glints, ${hits:-no} hits; expected >= 5 and >= 20"
    # 30 scans between two 6 m walls: nearly all matched, a keyframe per metre (2.4 m driven).
    ((${matched:-0} >= 20 && ${keyframes:-0} >= 2)) ||
      die "scan matching: ${matched:-no} scans matched, ${keyframes:-no} keyframes; expected >= 20 and >= 2"
    echo "$test_name: (4) ok: $glints laser glints, $hits tactical hits; $matched scans matched, $keyframes keyframes"
  else
    ((${glints:-0} == 0 && ${hits:-0} == 0)) || die "laser glints turned off, yet $glints glints and $hits hits"
    ((${matched:-0} == 0)) || die "scan matching turned off, yet $matched scans matched"
  fi
done
echo "$test_name: PASS"
