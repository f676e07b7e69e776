#!/usr/bin/env bash
# render.sh: smoke test of lasonic-render on the real pipeline's output (no network).
#  1. lasonic-sim (fig7_lab, 3 s) -> lasonic-replay -> lasonic-render at t = 2.5 s with the
#     scenario: exit 0, a PNG of the expected size that is not blank (read back with Cairo by
#     lasonic-render-check), and every panel whose channel the log lacks says so; with another
#     scenario's movers, or the robot's path moved 1.5 m, it says so and draws no truth.
#  2. --every 1: one frame per second of the log, each a valid PNG.
#  3. The raw simulator log (no pipeline channels): still a picture, the panels say what is missing.
#     --most-sonar: on the replayed log a moment inside it with its count of sonar sectors; on the
#     raw log (no SECTOR_MAP) a warning and the end; with --time, exit 2.
#  4. Bad input: missing, random and empty logs, a time outside the log, a bad scenario, bad
#     numbers (exit 2); an unwritable output (exit 1); a log with undecodable, truncated and
#     invalid messages at the moment drawn (exit 0, warned, the invalid panels say so).
set -euo pipefail
source "$(dirname "$0")/lib.sh"
die_globs+=('*.txt')

render=$bin/lasonic-render
check=$bin/lasonic-render-check
[[ -x $render ]] || die "$render was not built"
[[ -x $check ]] || die "$check was not built"

"$bin/lasonic-sim" --scenario "$scenario" --duration 3 --out "$tmp/sim.lcmlog" >"$tmp/sim.txt" 2>&1 ||
  die "lasonic-sim failed"
"$bin/lasonic-replay" --in "$tmp/sim.lcmlog" --out "$tmp/out.lcmlog" --config "$config" >"$tmp/replay.txt" 2>&1 ||
  die "lasonic-replay failed"

# Default panel 400 px: 4 x 400 wide, 30 (header) + 2 x 400 + 48 (legend) high.
W=1600 H=878

# ---- 1. one picture
"$render" --log "$tmp/out.lcmlog" --out "$tmp/a.png" --time 2.5 --scenario "$scenario" >"$tmp/a.txt" 2>&1 ||
  die "lasonic-render exited $? on the replayed log"
grep -q "wrote $tmp/a.png (1600 x 878 px, t = 2.50 s)" "$tmp/a.txt" || die "no 'wrote' line for t = 2.50 s"
"$check" png "$tmp/a.png" $W $H >"$tmp/a-check.txt" 2>&1 || die "a.png: $(cat "$tmp/a-check.txt")"
! grep -q "was not simulated from" "$tmp/a.txt" || die "the log's own scenario was called another's"
# A scenario with other movers (corridor_people's people; fig7_lab has none): said, no truth drawn.
"$render" --log "$tmp/out.lcmlog" --out "$tmp/other.png" --time 2.5 --scenario "$src/deploy/scenarios/corridor_people.yaml" \
  >"$tmp/other.txt" 2>&1 || die "lasonic-render exited $? with another scenario"
grep -q "was not simulated from .*corridor_people.yaml (its SIM_STATE has 0 movers, the scenario 3): no truth drawn" \
  "$tmp/other.txt" || die "another scenario's truth drawn without a word: $(cat "$tmp/other.txt")"
# The same scene with the robot's path 1.5 m to the side: movers and obstacles agree, the track not.
sed 's/^  path: \[\[1.0, 1.2\], \[7.0, 1.2\]/  path: [[1.0, 2.7], [7.0, 2.7]/' "$scenario" >"$tmp/moved_path.yaml"
cmp -s "$scenario" "$tmp/moved_path.yaml" && die "the moved path's sed changed nothing in $scenario"
"$render" --log "$tmp/out.lcmlog" --out "$tmp/moved.png" --time 2.5 --scenario "$tmp/moved_path.yaml" \
  >"$tmp/moved.txt" 2>&1 || die "lasonic-render exited $? with a moved path"
grep -q "was not simulated from .*moved_path.yaml (its robot's true pose (.*) is 1.5 m from the scenario's robot.path): no truth drawn" \
  "$tmp/moved.txt" || die "a moved path's truth drawn without a word: $(cat "$tmp/moved.txt")"
"$bin/lasonic-log-stats" "$tmp/out.lcmlog" >"$tmp/stats"
for ch in RADAR_MAP SONAR_HYPOTHESIS SONAR_RING SONAR_COMPLEMENT AGM_OPERATIONAL AGM_TACTICAL CURRENT_SENSOR_MAP SECTOR_MAP; do
  if [[ -z $(stat "$ch") ]]; then
    grep -q "no $ch in log" "$tmp/a.txt" || die "the log has no $ch, but no panel says so"
  else
    ! grep -q "no $ch" "$tmp/a.txt" || die "the log has $ch, but a panel says it has not"
  fi
done

# ---- 2. a frame sequence
"$render" --log "$tmp/out.lcmlog" --out "$tmp/seq/f.png" --every 1 >"$tmp/seq.txt" 2>&1 &&
  die "--every into a missing directory succeeded"
mkdir -p "$tmp/seq"
"$render" --log "$tmp/out.lcmlog" --out "$tmp/seq/f.png" --every 1 >"$tmp/seq.txt" 2>&1 || die "--every 1 failed"
n=$(find "$tmp/seq" -name 'f-*.png' | wc -l)
grep -q "lasonic-render: $n frames" "$tmp/seq.txt" || die "--every 1: $n files, but the tool says otherwise"
((n >= 3 && n <= 4)) || die "--every 1 over a 3 s log wrote $n frames"
for f in "$tmp"/seq/f-0000{0,1,2}.png; do
  "$check" png "$f" $W $H >"$tmp/seq-check.txt" 2>&1 || die "$f: $(cat "$tmp/seq-check.txt")"
done

for step in 1e-300 1e300; do
  rc=0
  "$render" --log "$tmp/out.lcmlog" --out "$tmp/seq/g.png" --every $step >"$tmp/step.txt" 2>&1 || rc=$?
  [[ $rc -eq 2 ]] && grep -q "must be a step of 0.001 to 1e6 s" "$tmp/step.txt" ||
    die "--every $step: exit status $rc: $(cat "$tmp/step.txt")"
done

# ---- 3. the raw simulator log
"$render" --log "$tmp/sim.lcmlog" --out "$tmp/raw.png" --scenario "$scenario" >"$tmp/raw.txt" 2>&1 ||
  die "lasonic-render failed on the raw simulator log"
grep -q "no RADAR_MAP in log" "$tmp/raw.txt" || die "raw log: the Radar Map panel does not say it is missing"
"$check" png "$tmp/raw.png" $W $H >"$tmp/raw-check.txt" 2>&1 || die "raw.png: $(cat "$tmp/raw-check.txt")"

# ---- 3b. --most-sonar
"$render" --log "$tmp/out.lcmlog" --out "$tmp/ms.png" --most-sonar >"$tmp/ms.txt" 2>&1 || die "--most-sonar failed"
grep -Eq "wrote $tmp/ms.png \(1600 x 878 px, t = [0-9.]+ s\)" "$tmp/ms.txt" || die "--most-sonar: no 'wrote' line"
n=$(sed -n 's/.*the most sectors from the sonar: \([0-9]*\) of.*/\1/p' "$tmp/ms.txt")
[[ -n $n ]] || die "--most-sonar: no count of sonar sectors"
((n >= 1)) || die "--most-sonar: $n sonar sectors, but the lab's first 3 s hear the fence"
"$check" png "$tmp/ms.png" $W $H >"$tmp/ms-check.txt" 2>&1 || die "ms.png: $(cat "$tmp/ms-check.txt")"
"$render" --log "$tmp/sim.lcmlog" --out "$tmp/ms-raw.png" --most-sonar >"$tmp/ms-raw.txt" 2>&1 ||
  die "--most-sonar failed on the raw simulator log"
grep -q "no SECTOR_MAP; drawing its end" "$tmp/ms-raw.txt" || die "--most-sonar on a log without SECTOR_MAP did not say so"
rc=0
"$render" --log "$tmp/out.lcmlog" --out "$tmp/ms2.png" --most-sonar --time 1 >"$tmp/ms2.txt" 2>&1 || rc=$?
((rc == 2)) || die "--most-sonar with --time: exit $rc (want 2)"

# ---- 4. bad input
expect_exit() {  # CODE NAME PATTERN ARGS...: lasonic-render ARGS exits CODE, its stderr matches PATTERN
  local code=$1 name=$2 pattern=$3 rc=0
  shift 3
  "$render" "$@" >"$tmp/$name.txt" 2>&1 || rc=$?
  [[ $rc -eq $code ]] || die "$name: exit status $rc, expected $code"
  grep -q -- "$pattern" "$tmp/$name.txt" || die "$name: the message does not say '$pattern'"
}
head -c 20000 /dev/urandom >"$tmp/random.lcmlog"
: >"$tmp/empty.lcmlog"
printf 'name: x\nobstacles: 3\n' >"$tmp/bad.yaml"
expect_exit 2 missing "cannot open" --log "$tmp/nonexistent.lcmlog" --out "$tmp/x.png"
expect_exit 2 random "no lasonic message" --log "$tmp/random.lcmlog" --out "$tmp/x.png"
expect_exit 2 empty "no lasonic message" --log "$tmp/empty.lcmlog" --out "$tmp/x.png"
expect_exit 2 late "outside the log" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --time 99
expect_exit 2 negative "--time" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --time -1
expect_exit 2 notnumber "time" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --time abc
expect_exit 2 every0 "--every" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --every 0
expect_exit 2 view "--view" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --view nan
expect_exit 2 scenario "bad scenario" --log "$tmp/out.lcmlog" --out "$tmp/x.png" --scenario "$tmp/bad.yaml"
expect_exit 1 unwritable "cannot open for writing" --log "$tmp/out.lcmlog" --out "$tmp/nodir/x.png"
[[ ! -e $tmp/x.png ]] || die "a failed run left $tmp/x.png"

"$check" corrupt "$tmp/out.lcmlog" "$tmp/bad.lcmlog" >"$tmp/corrupt.txt" 2>&1 || die "could not write the corrupt log"
"$render" --log "$tmp/bad.lcmlog" --out "$tmp/bad.png" --scenario "$scenario" >"$tmp/bad.txt" 2>&1 ||
  die "lasonic-render exited $? on a log with bad messages"
grep -q "warning: .* events did not decode" "$tmp/bad.txt" || die "bad log: undecodable events not reported"
grep -q "invalid AGM_OPERATIONAL message: ncells 10 != width\*height" "$tmp/bad.txt" ||
  die "bad log: the invalid AGM_OPERATIONAL is not reported"
grep -q "invalid SECTOR_MAP message: robot_pose not finite" "$tmp/bad.txt" ||
  die "bad log: the invalid SECTOR_MAP is not reported"
"$check" png "$tmp/bad.png" $W $H >"$tmp/bad-check.txt" 2>&1 || die "bad.png: $(cat "$tmp/bad-check.txt")"

echo "$test_name: PASS ($(cat "$tmp/a-check.txt"); $n frames)"
