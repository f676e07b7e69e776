#!/usr/bin/env bash
# fuzz_replay.sh [COUNT [SEED]]: the fuzz of fuzz.sh for the pipeline's channels (default 100000
# messages), written to a log and run through lasonic-replay (the complement and pilot stages,
# no network): deterministic, so a fault it finds is reproduced by the same seed. Every output
# must be valid (lasonic-fuzz check), and two replays must be bit-identical -- the second with
# every stage on one thread (--threads 1), its --status counters too.
# Then the tactical level, COUNT / 2 messages: the same kinds of fuzz on every input channel of the
# navigator (ODOMETRY, SONAR_COMPLEMENT, RADAR_MAP) through `lasonic-replay --stages navigator`,
# and on the pilot's with its remembered source on (ODOMETRY, LASER_SCAN, SONAR_COMPLEMENT,
# AGM_TACTICAL) through `--stages pilot`: outputs valid, and every message Node cannot decode (or
# finds over a cap) counted among the stage's input errors, and `--status` printing that total
# and the counters behind it. (Once each: the replay's determinism is checked above.)
# Env: LASONIC_BIN, LASONIC_SOURCE.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
count=${1:-100000}
seed=${2:-2}
"$bin/lasonic-fuzz" write "$tmp/fuzz.lcmlog" "$count" "$seed" || die "lasonic-fuzz write failed"
threads=("" "--threads 1")
for i in 1 2; do
  # shellcheck disable=SC2086  # (the option and its value as two words)
  "$bin/lasonic-replay" ${threads[i - 1]} --status --in "$tmp/fuzz.lcmlog" --out "$tmp/out$i.lcmlog" --config "$config" \
    >"$tmp/status$i.txt" 2>"$tmp/replay$i.err" || die "lasonic-replay ${threads[i - 1]} failed on the fuzz log"
done
cmp -s "$tmp/out1.lcmlog" "$tmp/out2.lcmlog" || die "two replays of the same fuzz log differ (default threads, --threads 1)"
cmp -s "$tmp/status1.txt" "$tmp/status2.txt" || die "the stages' counters differ between the default threads and --threads 1"
"$bin/lasonic-fuzz" check "$tmp/out1.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
  cat "$tmp/check.out"
  die "outputs of the fuzz log: $(head -5 "$tmp/check.err")"
}
cat "$tmp/check.out"
grep -h "input errors" "$tmp/replay1.err" || true

config_with pilot remembered true "$tmp/remembered.yaml"
"$bin/lasonic-fuzz" write "$tmp/tactical.lcmlog" $((count / 2)) "$seed" ODOMETRY,LASER_SCAN,SONAR_COMPLEMENT,RADAR_MAP,AGM_TACTICAL,AGM_LINES \
  >"$tmp/tactical.sent" || die "lasonic-fuzz write failed"
sent() { awk -v k="$1" '$1 == k {print $2}' "$tmp/tactical.sent"; }
# stage PROCESS STAGE OUTPUTS INPUTS: replay, check OUTPUTS, count errors on INPUTS.
stage() {
  local process=$1 stage=$2 outputs=$3 inputs=$4 errors need=0 ch
  "$bin/lasonic-replay" --stages "$stage" --in "$tmp/tactical.lcmlog" --out "$tmp/${stage}1.lcmlog" \
    --config "$tmp/remembered.yaml" --status >"$tmp/${stage}1.status" 2>"$tmp/${stage}1.err" ||
    die "lasonic-replay --stages $stage failed on the fuzz log"
  "$bin/lasonic-fuzz" check-only "$outputs" "$tmp/${stage}1.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
    cat "$tmp/check.out"
    die "$process's outputs under fuzzing: $(head -5 "$tmp/check.err")"
  }
  errors=$(sed -n "s/.*$process: \([0-9]*\) input errors.*/\1/p" "$tmp/${stage}1.err")
  for ch in ${inputs//,/ }; do need=$((need + $(sent "undecodable.$ch"))); done
  echo "$process: $(tr '\n' ' ' <"$tmp/check.out")input errors ${errors:-0}, undecodable on its inputs $need"
  ((${errors:-0} >= need && need > 0)) || die "$process counted ${errors:-0} input errors, fewer than the $need undecodable messages"
  # --status prints the same error total, and the counters that make it up.
  local st_errors st_rejected
  st_errors=$(awk -v p="$process" '$1 == p && $2 == "errors" {print $3}' "$tmp/${stage}1.status")
  [[ "$st_errors" == "$errors" ]] || die "$process: --status says ${st_errors:-nothing} errors, the log line $errors"
  st_rejected=$(awk -v p="$process" '$1 == p && $2 ~ /^(rejected|decode_errors|oversize)[.]/ {n += $3} END {print n + 0}' "$tmp/${stage}1.status")
  ((st_rejected >= need)) || die "$process: --status counts $st_rejected rejected or undecodable messages, fewer than the $need undecodable ones"
  grep -q "^$process last_error " "$tmp/${stage}1.status" || die "$process: --status gives no last_error"
}
echo "tactical fuzz: $(tr '\n' ' ' <"$tmp/tactical.sent")"
stage lasonic-navigator navigator AGM_TACTICAL,AGM_LINES,CURRENT_SENSOR_MAP ODOMETRY,SONAR_COMPLEMENT,RADAR_MAP
stage lasonic-pilot pilot SECTOR_MAP,AGM_OPERATIONAL ODOMETRY,LASER_SCAN,SONAR_COMPLEMENT,AGM_TACTICAL,AGM_LINES
grep -q "out.AGM_TACTICAL [1-9]" <("$bin/lasonic-fuzz" check-only AGM_TACTICAL "$tmp/navigator1.lcmlog") ||
  die "the navigator published no tactical map under fuzzing"
echo "$test_name: PASS ($count messages, then $((count / 2)) for the tactical level, seed $seed)"
