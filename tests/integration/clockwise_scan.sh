#!/usr/bin/env bash
# clockwise_scan.sh: a scanner mounted upside down (README "Channels", *A scan's direction*), on
# the offline pipeline (no network). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE.
#  1. The same readings sent clockwise: a simulated fig4_room log, and the same log with every
#     LASER_SCAN rewritten as a clockwise scanner sends it (lasonic-scan-reverse: arrays reversed,
#     each reading at its own time, angle_increment < 0), replayed and scored: the same scores,
#     within rounding (each reading's direction differs from the original by ~1e-16 rad), and the
#     complement reports no rejected laser scan or reading.
#     The same with a 270 deg scanner, whose view's edges the message swaps.
#  2. A scanner simulated clockwise (laser.sweep: clockwise, a 270 deg view) through the same
#     pipeline: its observable misses and the laser alone's misses within 0.02 of the
#     counter-clockwise scanner's (another run: each direction read at another moment), false
#     alarms at most 0.05.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
die_globs+=('*.table')

[[ -x $bin/lasonic-scan-reverse ]] || die "$bin/lasonic-scan-reverse was not built"
scene=$src/deploy/scenarios/fig4_room.yaml
# replay_and_score IN NAME [CONFIG...]: lasonic-replay IN -> $tmp/NAME.out, its table $tmp/NAME.table
replay_and_score() {
  local in=$1 name=$2
  shift 2
  local cfg=(--config "$config")
  for c in "$@"; do cfg+=(--config "$c"); done
  "$bin/lasonic-replay" --in "$in" --out "$tmp/$name.out" "${cfg[@]}" >"$tmp/$name-replay.err" 2>&1 ||
    die "$name: lasonic-replay failed: $(tail -n 3 "$tmp/$name-replay.err")"
  "$bin/lasonic-eval" --log "$tmp/$name.out" --scenario "$scene" "${cfg[@]}" >"$tmp/$name.table" \
    2>"$tmp/$name-eval.err" || die "$name: lasonic-eval failed: $(tail -n 3 "$tmp/$name-eval.err")"
}
value() { awk -v k="$2" '$1 == k {print $2}' "$tmp/$1.table"; }
# near NAME_A NAME_B KEY TOL: both have KEY, and they differ by at most TOL.
near() {
  local a b
  a=$(value "$1" "$3")
  b=$(value "$2" "$3")
  [[ -n $a && -n $b ]] || die "$3 missing ($1: '$a', $2: '$b')"
  awk -v a="$a" -v b="$b" -v t="$4" 'BEGIN {d = a - b; if (d < 0) d = -d; exit !(d <= t)}' ||
    die "$3: $1 $a, $2 $b: more than $4 apart"
  printf '%s %s / %s; ' "$3" "$a" "$b"
}

# 1. The same readings, sent clockwise: the 360 deg scanner, and a 270 deg one (its view's edges
#    swapped in the message).
printf 'laser:\n  fov_deg: 270\n  readings: 541\n' >"$tmp/ccw270.yaml"
printf 'laser:\n  fov_deg: 270\n  readings: 541\n  sweep: clockwise\n' >"$tmp/cw270.yaml"
same_readings() {  # NAME [CONFIG]: simulate, reverse, replay and score both; the same scores
  local n=$1 extra=()
  [[ $# -gt 1 ]] && extra=(--config "$2")
  "$bin/lasonic-sim" --scenario "$scene" --config "$config" "${extra[@]}" --duration 20 --out "$tmp/$n.raw" \
    >/dev/null 2>"$tmp/sim.err" || die "lasonic-sim ($n) failed: $(cat "$tmp/sim.err")"
  "$bin/lasonic-scan-reverse" "$tmp/$n.raw" "$tmp/$n-rev.raw" >"$tmp/reverse.out" || die "lasonic-scan-reverse failed"
  grep -qE 'lasonic-scan-reverse: [1-9][0-9]+ scans reversed' "$tmp/reverse.out" ||
    die "no scans reversed: $(cat "$tmp/reverse.out")"
  replay_and_score "$tmp/$n.raw" "$n" "${@:2}"
  replay_and_score "$tmp/$n-rev.raw" "$n-rev" "${@:2}"
  local out=""
  for key in sector_map.maps sector_map.samples.missed complement.samples.complementary complement.samples.redundant; do
    out+=$(near "$n" "$n-rev" "$key" 0)
  done
  for key in sector_map.observable_missed_rate sector_map.false_alarm_rate sector_map.false_alarm_share_of_reports; do
    out+=$(near "$n" "$n-rev" "$key" 0.0001)
  done
  echo "$test_name: (1) $n as sent / its readings sent clockwise: $out"
  "$bin/lasonic-log-stats" "$tmp/$n-rev.out" >"$tmp/stats" 2>/dev/null || die "log-stats failed"
  if grep -E '^lasonic-complement\.rejected\.laser' "$tmp/stats"; then
    die "the complement rejected laser input of the clockwise log"
  fi
}
same_readings ccw
same_readings ccw270 "$tmp/ccw270.yaml"
echo "$test_name: (1) ok"

# 2. A scanner simulated clockwise: each direction is read at another moment of the scan (and
#    with other noise draws), so the scores are another run's; a mirrored or misplaced scan would
#    put the laser's walls elsewhere and the laser alone would miss far more.
"$bin/lasonic-sim" --scenario "$scene" --config "$config" --config "$tmp/cw270.yaml" --duration 20 \
  --out "$tmp/cw270.raw" >/dev/null 2>"$tmp/sim.err" || die "lasonic-sim (cw270) failed: $(cat "$tmp/sim.err")"
replay_and_score "$tmp/cw270.raw" cw270 "$tmp/cw270.yaml"
out=""
for key in sector_map.observable_missed_rate baselines.laser_only.sector_map.missed_rate; do
  out+=$(near ccw270 cw270 "$key" 0.02)
done
fa=$(value cw270 sector_map.false_alarm_rate)
awk -v v="$fa" 'BEGIN {exit !(v <= 0.05)}' || die "cw270: false alarms $fa (at most 0.05)"
echo "$test_name: (2) ok: a 270 deg scanner simulated counter-clockwise / clockwise: $out false alarms $fa"
echo "$test_name: PASS"
