#!/usr/bin/env bash
# edge_scenes.sh: the offline pipeline (lasonic-sim -> lasonic-replay -> lasonic-eval, the shipped
# configuration) on scenes at the edges of what a user may write (no network). Env: LASONIC_BIN
# (build/bin), LASONIC_SOURCE (repository root).
#  1. an empty world: nothing within the scanner's or the sonar's range, so every report is a
#     false alarm; the sonar's foreign pings (a few per second) must not pass the operational
#     AGM's G_T of two: false alarms at most 0.01 of the sectors, no laser value at all;
#  2. a robot that stands still for the whole run (1 mm at 1 cm/s) beside a glass pane while a
#     person walks past: a sector map at least every map_max_interval_s, every rate in [0, 1];
#  3. a robot at 1.6 m/s (four times the suite's mean) along a corridor with glass, mesh, a black
#     box and a pipe: every rate in [0, 1];
#  4. a person who walks straight through the robot (the simulator's movers do not avoid it):
#     every rate in [0, 1];
#  5. a corridor 0.1 m wider than the robot: every rate in [0, 1].
# Every run exits 0 and scores every metric it prints as a finite number (a NaN fails the range
# check). The scenes are written here, so the test stands alone.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
die_globs+=('*.table')

# run NAME: $tmp/NAME.yaml through the pipeline; the table in $tmp/NAME.table.
run() {
  local n=$1
  "$bin/lasonic-sim" --scenario "$tmp/$n.yaml" --out "$tmp/$n.raw" --config "$config" >"$tmp/$n-sim.err" 2>&1 ||
    die "$n: lasonic-sim failed"
  "$bin/lasonic-replay" --in "$tmp/$n.raw" --out "$tmp/$n.out" --config "$config" >"$tmp/$n-replay.err" 2>&1 ||
    die "$n: lasonic-replay failed"
  "$bin/lasonic-eval" --log "$tmp/$n.out" --scenario "$tmp/$n.yaml" --config "$config" >"$tmp/$n.table" \
    2>"$tmp/$n-eval.err" || die "$n: lasonic-eval failed"
}
value() { awk -v k="$2" '$1 == k {print $2}' "$tmp/$1.table"; }
# rates NAME: every rate, share, recall, precision and coverage the table prints lies in [0, 1].
rates() {
  local bad
  bad=$(awk '$1 ~ /(rate|share|recall|precision|coverage|rejection|drop)$/ && !($2 + 0 == $2 && $2 >= 0 && $2 <= 1) {print}' \
    "$tmp/$1.table")
  [[ -z $bad ]] || die "$1: values outside [0, 1]: $bad"
  local n
  n=$(awk '$1 ~ /(rate|share|recall|precision|coverage)$/' "$tmp/$1.table" | wc -l)
  ((n >= 5)) || die "$1: only $n rates in the table"
}
# maps NAME SECONDS: at least one SECTOR_MAP per 0.1 s of the run.
maps() {
  local m
  m=$(value "$1" sector_map.maps)
  [[ -n $m ]] || die "$1: no sector_map.maps"
  awk -v m="$m" -v s="$2" 'BEGIN {exit !(m >= 10 * s)}' || die "$1: $m sector maps in $2 s"
}

cat >"$tmp/empty.yaml" <<'EOF'
name: empty
duration_s: 15
seed: 1
obstacles: []
robot: {radius: 0.35, path: [[0, 0], [5, 0]], speed: 0.5, mode: pingpong}
EOF
run empty
rates empty
maps empty 15
fa=$(value empty sector_map.false_alarm_rate)
[[ -n $fa ]] || die "empty: no sector_map.false_alarm_rate"
awk -v v="$fa" 'BEGIN {exit !(v <= 0.01)}' || die "empty: false alarms $fa in an empty world (at most 0.01)"
lr=$(value empty sensors.laser_no_return)
[[ $lr == 1.0000 ]] || die "empty: sensors.laser_no_return = $lr, expected 1 (nothing to return)"
echo "$test_name: (1) ok: empty world, false alarms $fa"

cat >"$tmp/still.yaml" <<'EOF'
name: still
duration_s: 15
seed: 2
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[-2, -2], [2, -2], [2, 2], [-2, 2]]}
  - {shape: segment, material: glass, from: [-1, 1], to: [1, 1]}
movers:
  - {shape: circle, radius: 0.25, material: person, speed: 0.8, path: [[-1.5, -1], [1.5, -1]], mode: pingpong}
robot: {radius: 0.35, path: [[0, 0], [0.001, 0]], speed: 0.01, mode: once}
EOF
run still
rates still
maps still 15
echo "$test_name: (2) ok: a robot standing still, missed $(value still sector_map.missed_rate)," \
  "false alarms $(value still sector_map.false_alarm_rate)"

cat >"$tmp/fast.yaml" <<'EOF'
name: fast
duration_s: 20
seed: 3
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[-1, -2], [21, -2], [21, 2], [-1, 2]]}
  - {shape: segment, material: glass, from: [5, 1.2], to: [8, 1.2]}
  - {shape: segment, material: mesh, from: [10, -1.1], to: [13, -1.1]}
  - {shape: box, material: black_cardboard, center: [15, 1.0], size: [0.5, 0.4], yaw_deg: 30}
  - {shape: circle, material: plastic, center: [17, -0.9], radius: 0.02}
robot: {radius: 0.35, path: [[0, 0], [20, 0]], speed: 1.6, mode: pingpong}
EOF
run fast
rates fast
maps fast 20
echo "$test_name: (3) ok: 1.6 m/s, missed $(value fast sector_map.missed_rate)," \
  "false alarms $(value fast sector_map.false_alarm_rate), tactical recall $(value fast agm_tactical.invisible_recall)"

cat >"$tmp/through.yaml" <<'EOF'
name: through
duration_s: 15
seed: 4
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0, 0], [8, 0], [8, 4], [0, 4]]}
movers:
  - {shape: circle, radius: 0.25, material: person, speed: 1.0, path: [[4, 0.5], [4, 3.5]], mode: pingpong}
robot: {radius: 0.35, path: [[1, 2], [7, 2]], speed: 0.4, mode: pingpong}
EOF
run through
rates through
maps through 15
echo "$test_name: (4) ok: a person walking through the robot, missed $(value through sector_map.missed_rate)"

cat >"$tmp/tight.yaml" <<'EOF'
name: tight
duration_s: 15
seed: 5
obstacles:
  - {shape: polyline, material: metal, closed: true, points: [[0, 0], [8, 0], [8, 0.8], [0, 0.8]]}
  - {shape: segment, material: glass, from: [3, 0.75], to: [5, 0.75]}
robot: {radius: 0.35, path: [[0.5, 0.4], [7.5, 0.4]], speed: 0.3, mode: pingpong}
EOF
run tight
rates tight
maps tight 15
echo "$test_name: (5) ok: a corridor 0.1 m wider than the robot, missed $(value tight sector_map.missed_rate)"
