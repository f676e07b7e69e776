#!/usr/bin/env bash
# eval_baselines.sh: lasonic-eval with --config on a short offline run (no network). Env:
# LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  1. lasonic-sim -> lasonic-replay -> lasonic-eval --config (the shipped file): exit 0, the
#     observability keys and every baseline's keys are in the JSON, all rates in [0, 1], and
#     laser-invisibility decided per scan (sensors.laser_truth = 1, no fallback warning);
#  2. the same twice gives identical JSON (deterministic); --complement-samples' columns average to
#     the complement's rates;
#  3. a missing config file, a bad baselines value and a misspelt section exit 2 and name the file
#     and key path; an empty log, and a log scored against a scenario it was not simulated from
#     (other movers, other obstacles, or a robot's path 1.5 m away from the log's track), exit 2
#     saying so (lasonic-log-stats too); the offline tools exit 0 on --help and 2 on any bad
#     command line, and 2 on an output that names one of their inputs (the input left intact);
#     lasonic-replay --print-config names the layer that set each key;
#  4. lasonic-eval-table: mean and worst over seeds, worst the highest rate and the lowest recall;
#     --summary over every run, --targets counting runs and scenes that meet each target;
#     one row per method (--methods), a run's keys looked up in its files of every folder.
set -euo pipefail

source "$(dirname "$0")/lib.sh"

"$bin/lasonic-sim" --scenario "$scenario" --out "$tmp/raw.lcmlog" --duration 6 >"$tmp/sim.err" 2>&1 ||
  die "lasonic-sim failed"
"$bin/lasonic-replay" --in "$tmp/raw.lcmlog" --out "$tmp/out.lcmlog" --config "$config" >"$tmp/replay.err" 2>&1 ||
  die "lasonic-replay failed"
for i in 1 2; do
  "$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$scenario" --config "$config" --json "$tmp/eval$i.json" \
    >"$tmp/table$i.txt" 2>"$tmp/eval.err" || die "lasonic-eval failed"
done
# The table has one "dotted.key value" line per metric.
value() { awk -v k="$1" '$1 == k {print $2}' "$tmp/table1.txt"; }
check() {  # KEY MAX: present, in [0, MAX]
  local v
  v=$(value "$1")
  [[ -n $v ]] || die "no $1 in the table"
  awk -v v="$v" -v max="$2" 'BEGIN {exit !(v >= 0 && v <= max)}' || die "$1 = $v not in [0, $2]"
}
for k in missed_rate observable_missed_rate unobservable_share false_alarm_rate false_alarm_share_of_reports; do
  check "sector_map.$k" 1
done
check sector_map.mae_m 10
# A simulated log has LASER_TRUTH: "laser-invisible" is decided per scan, not by material.
[[ $(value sensors.laser_truth) == 1 ]] || die "sensors.laser_truth = '$(value sensors.laser_truth)', expected 1"
grep -q "LASER_TRUTH" "$tmp/eval.err" && die "lasonic-eval warns about LASER_TRUTH on a simulated log"
grep -q '^ *sector_map\.missed_by_material\.' "$tmp/table1.txt" || die "no sector_map.missed_by_material.*"
for name in laser_only sonar_himm naive_fusion log_odds; do
  for k in missed_rate observable_missed_rate false_alarm_rate false_alarm_share_of_reports; do
    check "baselines.$name.sector_map.$k" 1
  done
  echo "  $name: missed $(value "baselines.$name.sector_map.missed_rate")," \
    "false alarms $(value "baselines.$name.sector_map.false_alarm_rate")"
done
cmp -s "$tmp/eval1.json" "$tmp/eval2.json" || die "two evaluations of the same log differ"
# --complement-samples: a row per classified reading; a rate's column, averaged, is the rate.
"$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$scenario" --config "$config" \
  --complement-samples "$tmp/complement.csv" >/dev/null 2>&1 || die "lasonic-eval --complement-samples failed"
for k in invisible:invisible_recall redundant:redundant_drop complementary:precision; do
  column_mean=$(awk -F, -v c="${k%%:*}" 'NR == 1 {for (i = 1; i <= NF; ++i) if ($i == c) col = i; next}
    $col != "" {n += 1; s += $col} END {if (col && n) printf "%.6f", s / n}' "$tmp/complement.csv")
  rate=$(value "complement.${k#*:}")
  [[ -n $column_mean && -n $rate ]] && awk -v a="$column_mean" -v b="$rate" 'BEGIN {exit !(a - b < 1e-3 && b - a < 1e-3)}' ||
    die "--complement-samples: column ${k%%:*} averages '$column_mean', complement.${k#*:} is '$rate'"
done
echo "$test_name: (1, 2) ok: observability and baseline keys present, deterministic"

expect_error() {  # CASE WANT ARGS...
  local case=$1 want=$2 rc=0
  shift 2
  "$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$scenario" "$@" >"$tmp/$case.err" 2>&1 || rc=$?
  [[ $rc -eq 2 ]] || die "$case: exit status $rc, expected 2"
  grep -qF -- "$want" "$tmp/$case.err" || die "$case: the message does not say '$want'"
  echo "  ($case) $(head -n 1 "$tmp/$case.err")"
}
expect_error missing_config "$tmp/none.yaml: cannot open file" --config "$tmp/none.yaml"
# A log scored against a scenario it was not simulated from: no numbers, an error naming both.
for other in corridor_people:SIM_STATE fig4_room:LASER_TRUTH; do
  rc=0
  "$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$src/deploy/scenarios/${other%%:*}.yaml" >"$tmp/other.err" 2>&1 || rc=$?
  [[ $rc -eq 2 ]] || die "scored against ${other%%:*}: exit status $rc, expected 2"
  grep -qF "was not simulated from $src/deploy/scenarios/${other%%:*}.yaml: its ${other#*:}" "$tmp/other.err" ||
    die "scored against ${other%%:*}: $(cat "$tmp/other.err")"
  echo "  (against ${other%%:*}) $(head -n 1 "$tmp/other.err")"
done
# The same scene with the robot's path moved by a metre and a half: its obstacles and movers are
# the log's, its robot's track is not.
sed 's/^  path: \[\[1.0, 1.2\], \[7.0, 1.2\]/  path: [[1.0, 2.7], [7.0, 2.7]/' "$scenario" >"$tmp/moved_path.yaml"
cmp -s "$scenario" "$tmp/moved_path.yaml" && die "the moved path's sed changed nothing in $scenario"
rc=0
"$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$tmp/moved_path.yaml" >"$tmp/moved.err" 2>&1 || rc=$?
[[ $rc -eq 2 ]] || die "scored against a moved path: exit status $rc, expected 2"
grep -qF "was not simulated from $tmp/moved_path.yaml: at t = " "$tmp/moved.err" &&
  grep -qF "m from the scenario's robot.path" "$tmp/moved.err" || die "scored against a moved path: $(cat "$tmp/moved.err")"
echo "  (against a moved path) $(head -n 1 "$tmp/moved.err")"
: >"$tmp/empty.lcmlog"
rc=0
"$bin/lasonic-eval" --log "$tmp/empty.lcmlog" --scenario "$scenario" >"$tmp/empty_log.err" 2>&1 || rc=$?
[[ $rc -eq 2 ]] || die "an empty log: exit status $rc, expected 2"
grep -qF "empty.lcmlog: no lasonic message on any scored channel" "$tmp/empty_log.err" ||
  die "an empty log: the message does not say so: $(cat "$tmp/empty_log.err")"
# --out naming the input log (before, it was truncated to nothing first).
size=$(command stat -c %s "$tmp/raw.lcmlog")
rc=0
"$bin/lasonic-replay" --in "$tmp/raw.lcmlog" --out "$tmp/./raw.lcmlog" >"$tmp/same.err" 2>&1 || rc=$?
[[ $rc -eq 2 && $(command stat -c %s "$tmp/raw.lcmlog") -eq $size ]] && grep -qF "is the input log" "$tmp/same.err" ||
  die "lasonic-replay --out = --in: exit status $rc, $(command stat -c %s "$tmp/raw.lcmlog") of $size bytes left: $(cat "$tmp/same.err")"
# lasonic-replay: --in and --out are required (exit 2 naming the missing one), except with
# --print-config, which prints what the three stages read and which layer set it, reading no log.
rc=0
"$bin/lasonic-replay" --in "$tmp/raw.lcmlog" >"$tmp/noout.err" 2>&1 || rc=$?
[[ $rc -eq 2 ]] && grep -qF -- "--out is required" "$tmp/noout.err" ||
  die "lasonic-replay without --out: exit status $rc: $(cat "$tmp/noout.err")"
printf 'navigator:\n  hit_weight_low_speed: 0\n' >"$tmp/overlay.yaml"
"$bin/lasonic-replay" --config "$config" --config "$tmp/overlay.yaml" --print-config >"$tmp/print.out" 2>&1 ||
  die "lasonic-replay --print-config: exit $?: $(cat "$tmp/print.out")"
for want in "navigator.hit_weight_low_speed: 0  # $tmp/overlay.yaml" "navigator.hit_weight_speed: 0.4  # $config" \
  "complement.tolerance: 0.1  # $config"; do
  grep -qxF -- "$want" "$tmp/print.out" || die "lasonic-replay --print-config: no line '$want'"
done
# No other output over an input either: each case exits 2 naming both, and the input is intact.
cp "$config" "$tmp/cfg.yaml"
cp "$scenario" "$tmp/scene.yaml"
cp "$tmp/out.lcmlog" "$tmp/keep.lcmlog"
not_overwritten() {  # FILE WANT TOOL ARGS...
  local file=$1 want=$2 before rc=0
  shift 2
  before=$(md5sum <"$file")
  "$bin/$1" "${@:2}" >"$tmp/over.err" 2>&1 || rc=$?
  [[ $rc -eq 2 && $(md5sum <"$file") == "$before" ]] && grep -qF -- "$want" "$tmp/over.err" ||
    die "$*: exit status $rc, $file changed or not named: $(cat "$tmp/over.err")"
}
not_overwritten "$tmp/cfg.yaml" "--out $tmp/cfg.yaml is the --config file" \
  lasonic-replay --in "$tmp/raw.lcmlog" --out "$tmp/cfg.yaml" --config "$tmp/cfg.yaml"
not_overwritten "$tmp/keep.lcmlog" "--json $tmp/./keep.lcmlog is the --log file" \
  lasonic-eval --log "$tmp/keep.lcmlog" --scenario "$tmp/scene.yaml" --json "$tmp/./keep.lcmlog"
not_overwritten "$tmp/scene.yaml" "--samples $tmp/scene.yaml is the --scenario file" \
  lasonic-eval --log "$tmp/keep.lcmlog" --scenario "$tmp/scene.yaml" --samples "$tmp/scene.yaml"
not_overwritten "$tmp/cfg.yaml" "--tactical-samples $tmp/cfg.yaml is the --config file" \
  lasonic-eval --log "$tmp/keep.lcmlog" --scenario "$tmp/scene.yaml" --config "$tmp/cfg.yaml" --tactical-samples "$tmp/cfg.yaml"
not_overwritten "$tmp/keep.lcmlog" "--complement-samples $tmp/keep.lcmlog is the --log file" \
  lasonic-eval --log "$tmp/keep.lcmlog" --scenario "$tmp/scene.yaml" --complement-samples "$tmp/keep.lcmlog"
if [[ -x $bin/lasonic-lossy-relay ]]; then
  not_overwritten "$tmp/keep.lcmlog" "--out-log $tmp/keep.lcmlog is the --in-log file" \
    lasonic-lossy-relay --in-log "$tmp/keep.lcmlog" --out-log "$tmp/keep.lcmlog" --loss 0.2
fi
rc=0
"$bin/lasonic-log-stats" "$tmp/empty.lcmlog" >"$tmp/empty_stats.err" 2>&1 || rc=$?
[[ $rc -eq 2 ]] && grep -qF "empty.lcmlog: no event in the log" "$tmp/empty_stats.err" ||
  die "lasonic-log-stats on an empty log: exit status $rc: $(cat "$tmp/empty_stats.err")"
printf 'baselines:\n  sonar_himm:\n    threshold: 99\n' >"$tmp/bad.yaml"
expect_error bad_value "bad.yaml: baselines.sonar_himm.threshold" --config "$tmp/bad.yaml"
printf 'baselines:\n  log_odds:\n    size: 40\n' >"$tmp/small.yaml"
expect_error small_window "small.yaml: baselines.log_odds.size" --config "$tmp/small.yaml"
printf 'pilto:\n  robot_radius: 0.27\n' >"$tmp/typo.yaml"
expect_error misspelt_section "typo.yaml: pilto: unknown key" --config "$config" --config "$tmp/typo.yaml"
echo "$test_name: (3) ok: bad configuration exits 2 naming the file and key"

# (3b) The offline tools' command lines: --help exits 0, an unknown option, a missing required one
# or a misspelt configuration section exits 2 (README "Processes: start-up, exit codes, status").
expect_rc() {  # WANT CASE TOOL ARGS...
  local want=$1 case=$2 tool=$3 rc=0
  shift 3
  "$bin/$tool" "$@" >"$tmp/cli.$case.out" 2>&1 || rc=$?
  [[ $rc -eq $want ]] || die "$tool ($case): exit status $rc, expected $want: $(tail -n 2 "$tmp/cli.$case.out")"
}
# (Each with its required options, so that the unknown one is what is refused.)
declare -A required=(
  [lasonic-sim]="--scenario $scenario --out $tmp/x.lcmlog" [lasonic-replay]="--in $tmp/raw.lcmlog --out $tmp/x.lcmlog"
  [lasonic-eval]="--log $tmp/out.lcmlog --scenario $scenario" [lasonic-eval-table]="$tmp/eval1.json"
  [lasonic-scenegen]="--out $tmp/scenes"
)
for tool in lasonic-sim lasonic-replay lasonic-eval lasonic-eval-table lasonic-scenegen; do
  expect_rc 0 "$tool-help" "$tool" --help
  # shellcheck disable=SC2086  # the required options are words
  expect_rc 2 "$tool-unknown" "$tool" ${required[$tool]} --no-such-option
  grep -q "^$tool: .*no-such-option" "$tmp/cli.$tool-unknown.out" ||
    die "$tool: the unknown option is not what was refused: $(cat "$tmp/cli.$tool-unknown.out")"
done
expect_rc 2 sim-required lasonic-sim --out "$tmp/x.lcmlog"
expect_rc 2 replay-required lasonic-replay --out "$tmp/x.lcmlog"
expect_rc 2 replay-range lasonic-replay --in "$tmp/raw.lcmlog" --out "$tmp/x.lcmlog" --threads 99
expect_rc 2 replay-typo lasonic-replay --in "$tmp/raw.lcmlog" --out "$tmp/x.lcmlog" --config "$config" --config "$tmp/typo.yaml"
grep -qF "typo.yaml: pilto: unknown key" "$tmp/cli.replay-typo.out" || die "lasonic-replay does not name the misspelt section"
expect_rc 2 replay-missing-config lasonic-replay --in "$tmp/raw.lcmlog" --out "$tmp/x.lcmlog" --config "$tmp/none.yaml"
grep -qF "$tmp/none.yaml: cannot open file" "$tmp/cli.replay-missing-config.out" ||
  die "lasonic-replay: no 'cannot open file' for a missing --config: $(cat "$tmp/cli.replay-missing-config.out")"
expect_rc 2 sim-typo lasonic-sim --scenario "$scenario" --out "$tmp/x.lcmlog" --config "$tmp/typo.yaml"
# A file with no LCM event is an error; a log cut short is replayed up to the cut, and said so.
head -c 20000 /dev/urandom >"$tmp/random.lcmlog"
expect_rc 2 replay-random lasonic-replay --in "$tmp/random.lcmlog" --out "$tmp/x.lcmlog"
grep -qF "random.lcmlog: no LCM event in the file" "$tmp/cli.replay-random.out" || die "lasonic-replay: random bytes not named"
head -c $(($(stat -c %s "$tmp/raw.lcmlog") - 30)) "$tmp/raw.lcmlog" >"$tmp/cut.lcmlog"
expect_rc 0 replay-cut lasonic-replay --in "$tmp/cut.lcmlog" --out "$tmp/x.lcmlog" --config "$config"
grep -qF "cut.lcmlog: the log ends at byte" "$tmp/cli.replay-cut.out" || die "lasonic-replay: a cut log not said: $(cat "$tmp/cli.replay-cut.out")"
echo "$test_name: (3b) ok: the offline tools exit 0 on --help and 2 on a bad command line or section, or on a file with no event"

# (4) Two seeds of one scene: a rate's worst is its highest value, a recall's its lowest.
mkdir -p "$tmp/table"
printf '{"sector_map": {"missed_rate": 0.02, "x_recall": 0.9}}\n' >"$tmp/table/room-s1.json"
printf '{"sector_map": {"missed_rate": 0.04, "x_recall": 0.7}}\n' >"$tmp/table/room-s2.json"
"$bin/lasonic-eval-table" "$tmp"/table/*.json --keys sector_map.missed_rate,sector_map.x_recall,sector_map.none \
  >"$tmp/table.md" || die "lasonic-eval-table failed"
grep -qF '| sector_map.x_recall (worst: lowest) |' "$tmp/table.md" || die "the recall column does not say its worst is the lowest"
grep -qF '| room | 2 | 0.030 (0.040) | 0.800 (0.700) | - | 2 |' "$tmp/table.md" ||
  die "lasonic-eval-table: expected '| room | 2 | 0.030 (0.040) | 0.800 (0.700) | - | 2 |', got: $(tail -n 1 "$tmp/table.md")"
echo "$test_name: (4) ok: lasonic-eval-table's worst is the highest rate and the lowest recall"

# (4b) One run scored by two programs (files of one name in two folders), one row per method.
mkdir -p "$tmp/t2/eval" "$tmp/t2/peer"
for seed in 1 2; do
  printf '{"sector_map": {"missed_rate": 0.0%d}, "baselines": {"log_odds": {"sector_map": {"missed_rate": 0.1%d}}}}\n' \
    "$seed" "$seed" >"$tmp/t2/eval/room-s$seed.json"
  printf '{"mrpt": {"sector_map": {"missed_rate": 0.2%d}}}\n' "$seed" >"$tmp/t2/peer/room-s$seed.json"
done
"$bin/lasonic-eval-table" "$tmp"/t2/eval/*.json "$tmp"/t2/peer/*.json --keys missed_rate \
  --methods "lasonic=sector_map,log-odds=baselines.log_odds.sector_map,MRPT=mrpt.sector_map,none=nothing" \
  >"$tmp/t2.md" || die "lasonic-eval-table --methods failed"
for want in '| room | lasonic | 2 | 0.015 (0.020) | 0 |' '| room | log-odds | 2 | 0.115 (0.120) | 0 |' \
  '| room | MRPT | 2 | 0.215 (0.220) | 0 |' '| room | none | 2 | - | 2 |'; do
  grep -qF -- "$want" "$tmp/t2.md" || die "lasonic-eval-table --methods: no line '$want' in: $(cat "$tmp/t2.md")"
done
"$bin/lasonic-eval-table" "$tmp"/t2/eval/*.json --keys missed_rate --methods "nameless" >/dev/null 2>"$tmp/t2.err" &&
  die "--methods without NAME=PREFIX was accepted"
grep -qF "'nameless' is not NAME=PREFIX" "$tmp/t2.err" || die "--methods: the error does not name the bad entry"
echo "$test_name: (4b) ok: one row per method, a run's files of both folders read together"

# (4c) --summary: one more row over every run of every scene; --targets: runs and scenes meeting.
printf '{"sector_map": {"missed_rate": 0.10, "x_recall": 0.5}, "lo": 0.05}\n' >"$tmp/table/hall-s1.json"
"$bin/lasonic-eval-table" "$tmp"/table/*.json --summary --keys sector_map.missed_rate >"$tmp/sum.md" ||
  die "lasonic-eval-table --summary failed"
grep -qF '| **all 2 scenes** | 3 runs | 0.053 (0.100) | 0 |' "$tmp/sum.md" ||
  die "--summary: expected '| **all 2 scenes** | 3 runs | 0.053 (0.100) | 0 |' in: $(cat "$tmp/sum.md")"
"$bin/lasonic-eval-table" "$tmp"/table/*.json \
  --targets "sector_map.missed_rate<=0.03,sector_map.x_recall>=0.75,sector_map.missed_rate<lo" >"$tmp/tg.md" ||
  die "lasonic-eval-table --targets failed"
for want in '| sector_map.missed_rate<=0.03 | 1 of 3 | 0 of 2 |' '| sector_map.x_recall>=0.75 | 1 of 3 | 0 of 2 |' \
  '| sector_map.missed_rate<lo | 0 of 3 | 0 of 2 |' '| all of them | 0 of 3 | 0 of 2 |'; do
  grep -qF -- "$want" "$tmp/tg.md" || die "--targets: no line '$want' in: $(cat "$tmp/tg.md")"
done
"$bin/lasonic-eval-table" "$tmp"/table/*.json --targets "sector_map.missed_rate" >/dev/null 2>"$tmp/tg.err" &&
  die "--targets without a comparison was accepted"
grep -qF "'sector_map.missed_rate' is not KEY<=VALUE" "$tmp/tg.err" || die "--targets: the error does not name the bad entry"
echo "$test_name: (4c) ok: --summary over every run, --targets counts runs and scenes"

# (4d) --glance: the set as one row of README Results' At a glance: means over the runs that have
# each key, runs meeting every (default) target and scenes meeting them on every seed.
mkdir -p "$tmp/glance"
run_json() {  # SCENE SEED OBSERVABLE_MISSED FALSE_ALARMS SHARE MISSED LASER_MISSED [RECALL]
  local tactical=
  [[ -z ${8:-} ]] || tactical=", \"agm_tactical\": {\"invisible_recall\": $8, \"precision\": 0.9}"
  local sm='"observable_missed_rate": %s, "false_alarm_rate": %s, "false_alarm_share_of_reports": %s'
  printf "{\"sector_map\": {$sm, \"samples\": {\"missed\": %s}}, \"baselines\": {\"laser_only\": %s}%s}\n" \
    "$3" "$4" "$5" "$6" "{\"sector_map\": {\"samples\": {\"missed\": $7}}}" "$tactical" >"$tmp/glance/$1-s$2.json"
}
run_json room 1 0.01 0.02 0.05 10 20 0.8
run_json room 2 0.02 0.03 0.06 10 20 0.6
run_json hall 1 0.04 0.01 0.02 10 20          # observable missed above 0.03, and no tactical keys
run_json hall 2 0.01 0.01 0.03 30 20          # more misses than the laser alone
"$bin/lasonic-eval-table" "$tmp"/glance/*.json --glance "two rooms" >"$tmp/glance.md" ||
  die "lasonic-eval-table --glance failed"
want='| two rooms | 4 | 0.0200 | 0.0175 | 0.040 | 2 (1 of 2) | 0.700 / 0.900 | - / - |'
grep -qF -- "$want" "$tmp/glance.md" || die "--glance: expected '$want' in: $(cat "$tmp/glance.md")"
"$bin/lasonic-eval-table" "$tmp"/glance/*.json --glance "loose" --targets "sector_map.false_alarm_rate<=0.05" \
  >"$tmp/glance2.md" || die "lasonic-eval-table --glance --targets failed"
grep -qF -- '| loose | 4 | 0.0200 | 0.0175 | 0.040 | 4 (2 of 2) |' "$tmp/glance2.md" ||
  die "--glance with --targets: got $(tail -n 1 "$tmp/glance2.md")"
echo "$test_name: (4d) ok: --glance gives the set's At a glance row"
