#!/usr/bin/env bash
# faults.sh: the pilot host (deploy/hosts/pilot.yaml, fig7_lab) under lasonic-launch, with faults
# injected while lcm-logger records. Run it inside a private network namespace (ctest does).
# Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  - kill -9 of every process in turn (complement, pilot, laser driver, sonar driver, sim-world):
#    the launcher restarts it; measured per process: the time from the kill to its first output
#    (output_s) and until SECTOR_MAP is fresh again (both sensors fresh) for good (recovered_s);
#    must be < 3 s;
#  - a sensor driver frozen (SIGSTOP) for 2 s, laser then sonar: SECTOR_MAP flags it stale (at an
#    age within two sensor periods plus the map's own period) and never reports more free space
#    than its last fresh map (lasonic-fault-check stale);
#  - sim-world's restart starts its clock again: every process counts a time reset and recovers.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
url+='&recv_buf_size=4194304'
die_globs+=('launch.txt' 'out/*.txt')
check=$bin/lasonic-fault-check
cd "$src"   # the profile's paths are relative to the repository root

now_us() { date +%s%6N; }
pid_of() { sed -n "s/.*\] $1 started (pid \([0-9]*\)).*/\1/p" "$tmp/launch.txt" | tail -1; }

start_logger run.lcmlog
"$bin/lasonic-launch" deploy/hosts/pilot.yaml --bin "$bin" --lcm-url "$url" --log-dir "$tmp/out" \
  --max-time 120 2>"$tmp/launch.txt" &
launcher=$!
pids+=("$launcher")
t0=$(now_us)
at() {  # at SECONDS: sleep until SECONDS after t0
  local due=$((t0 + ${1/./} * 100000)) n
  n=$(now_us)
  ((due > n)) && sleep "$(awk -v d=$((due - n)) 'BEGIN { printf "%.3f", d / 1e6 }')"
  return 0
}

procs=(lasonic-complement lasonic-pilot lasonic-laser-driver lasonic-sonar-driver lasonic-sim-world)
outputs=(SONAR_COMPLEMENT SECTOR_MAP LASER_SCAN SONAR_RING ODOMETRY)
declare -A kill_t
at 4.0
for i in "${!procs[@]}"; do
  p=${procs[$i]}
  [[ $p == lasonic-sim-world ]] && at 24.0
  pid=$(pid_of "$p")
  [[ -n $pid ]] && kill -0 "$pid" 2>/dev/null || die "$p is not running before its kill"
  kill -9 "$pid"
  kill_t[$p]=$(now_us)
  echo "kill -9 $p (pid $pid)"
  if [[ $p == lasonic-sonar-driver ]]; then
    at 15.0
    laser=$(pid_of lasonic-laser-driver); kill -STOP "$laser"; stop_laser=$(now_us)
    at 17.0
    kill -CONT "$laser"; cont_laser=$(now_us)
    at 19.0
    sonar=$(pid_of lasonic-sonar-driver); kill -STOP "$sonar"; stop_sonar=$(now_us)
    at 21.0
    kill -CONT "$sonar"; cont_sonar=$(now_us)
  else
    at $((4 + 3 * (i + 1))).0
  fi
done
at 29.0
kill -TERM "$launcher"
rc=0
wait "$launcher" || rc=$?
sleep 0.3
stop_logger
((rc == 0)) || die "lasonic-launch exited with status $rc after SIGTERM"
cat "$tmp/launch.txt"

# Every kill was answered by exactly one restart, and nothing else died.
for p in "${procs[@]}"; do
  n=$(grep -c "\] $p started" "$tmp/launch.txt")
  [[ $n == 2 ]] || die "$p was started $n times, expected 2 (once, and once after its kill)"
done
grep -E 'exited with status [1-9]|on stopping' "$tmp/launch.txt" && die "a process failed (see above)"

ends=("${kill_t[lasonic-pilot]}" "${kill_t[lasonic-laser-driver]}" "${kill_t[lasonic-sonar-driver]}" "$stop_laser"
      $((kill_t[lasonic-sim-world] + 4000000)))
echo "process output_s recovered_s"
for i in "${!procs[@]}"; do
  p=${procs[$i]}
  "$check" recovery "$tmp/run.lcmlog" "${kill_t[$p]}" "${ends[$i]}" "${outputs[$i]}" >"$tmp/rec.txt" ||
    die "$p: no recovery after its kill: $(tr '\n' ' ' <"$tmp/rec.txt")"
  out=$(awk '$1 == "output_s" {print $2}' "$tmp/rec.txt")
  recd=$(awk '$1 == "recovered_s" {print $2}' "$tmp/rec.txt")
  echo "recovery $p $out $recd"
  awk -v r="$recd" 'BEGIN { exit !(r < 3.0) }' || die "$p took $recd s to recover (limit 3 s)"
done

for s in laser sonar; do
  if [[ $s == laser ]]; then a=$stop_laser; b=$cont_laser; period=0.2; else a=$stop_sonar; b=$cont_sonar; period=0.18; fi
  "$check" stale "$tmp/run.lcmlog" "$a" "$b" "$s" >"$tmp/stale.txt" || {
    cat "$tmp/stale.txt"
    die "$s frozen: the sector map did not flag it stale, or reported more free space than its last fresh map"
  }
  age=$(awk '$1 == "stale_age_s" {print $2}' "$tmp/stale.txt")
  echo "stale $s $(tr '\n' ' ' <"$tmp/stale.txt")"
  # Stale once two sensor periods have passed (the thresholds), said by the next map: one is made
  # at least every map_max_interval_s = 0.1 s, on the first ODOMETRY (20 ms ticks) after that.
  awk -v a="$age" -v p="$period" 'BEGIN { exit !(a > 0 && a <= 2 * p + 0.12 + 1e-3) }' ||
    die "$s: flagged stale at an age of $age s, expected within two periods ($period s) + 0.12 s"
done

# The world's restart: every process noticed the clock starting again.
"$bin/lasonic-log-stats" "$tmp/run.lcmlog" >"$tmp/stats"
for p in lasonic-complement lasonic-pilot lasonic-laser-driver lasonic-sonar-driver; do
  n=$(stat "$p.time_resets")
  [[ -n $n && $n -ge 1 ]] || die "$p did not count a time reset after lasonic-sim-world restarted"
done
echo "$test_name: PASS"
