#!/usr/bin/env bash
# launch.sh: lasonic-launch's process handling, with plain shell processes (no LCM, no network).
# Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  1. a profile naming a missing executable: exit 2, the message names it; optional: started anyway;
#     --check names a --config file that is not there, also as --config=FILE, an empty lcm_url,
#     and a bad key in a process's configuration (exit 2); --print-config prints each process's
#     configuration in effect; --max-time nan/inf/1e300 and a start_delay_s of 1e300 are errors (exit 2);
#  2. a process that always fails is restarted with a doubling back-off (0.2, 0.4, 0.8 s);
#     kill -9 of a long-running one: restarted after the initial delay, its log has a second start;
#     a `finish` process ends the run: every other process is stopped, in reverse order, exit 0,
#     no process left over; one that ignores SIGINT is killed after stop_timeout_s;
#  3. SIGTERM to the launcher stops every process and exits 0;
#  4. a process that exits 2 (bad configuration) is not restarted; the launcher exits 2 at the end.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
launch=$bin/lasonic-launch
die_globs+=('launch*.txt' 'logs*/*.txt')

# 1. Missing executables.
cat >"$tmp/missing.yaml" <<'YAML'
lcm_url: memq://
processes:
  - {name: real, command: [sleep, "0.2"], restart: never}
  - {name: ghost, command: [lasonic-no-such-program]}
YAML
rc=0
"$launch" "$tmp/missing.yaml" --log-dir "$tmp/logs1" 2>"$tmp/launch1.txt" || rc=$?
((rc == 2)) || die "a missing executable: exit $rc, expected 2"
grep -q "ghost: executable 'lasonic-no-such-program' not found" "$tmp/launch1.txt" || die "the missing executable is not named"
sed -i 's/command: \[lasonic-no-such-program\]}/command: [lasonic-no-such-program], optional: true}/' "$tmp/missing.yaml"
"$launch" "$tmp/missing.yaml" --log-dir "$tmp/logs1" 2>"$tmp/launch1b.txt" || die "optional missing: exit $?"
grep -q "optional, not started" "$tmp/launch1b.txt" || die "the optional missing executable is not reported"
# --check says when a --config or --scenario file is not there (relative to where it runs).
cat >"$tmp/files.yaml" <<'YAML'
lcm_url: memq://
processes:
  - {name: p, command: [sleep, --config, no-such-config.yaml]}
YAML
rc=0
(cd "$tmp" && "$launch" files.yaml --check) >"$tmp/launch1c.txt" 2>&1 || rc=$?
((rc == 2)) || die "--check with a missing --config file: exit $rc, expected 2"
grep -q "p: --config no-such-config.yaml: no such file" "$tmp/launch1c.txt" || die "the missing file is not named"
# ... in the --config=FILE form too; an empty lcm_url is an error.
cat >"$tmp/files2.yaml" <<'YAML'
lcm_url: memq://
processes:
  - {name: p, command: [sleep, --config=no-such-config.yaml]}
YAML
rc=0
(cd "$tmp" && "$launch" files2.yaml --check) >"$tmp/launch1d.txt" 2>&1 || rc=$?
((rc == 2)) || die "--check with a missing --config=FILE: exit $rc, expected 2"
grep -q "p: --config no-such-config.yaml: no such file" "$tmp/launch1d.txt" || die "the missing --config=FILE is not named"
sed -i 's|lcm_url: memq://|lcm_url: ""|' "$tmp/files2.yaml"
rc=0
"$launch" "$tmp/files2.yaml" --check >"$tmp/launch1e.txt" 2>&1 || rc=$?
((rc == 2)) || die "--check with lcm_url \"\": exit $rc, expected 2"
grep -q "lcm_url: must not be empty" "$tmp/launch1e.txt" || die "the empty lcm_url is not named: $(cat "$tmp/launch1e.txt")"
# --check loads each lasonic process's configuration as the process would (--check-config): a
# bad key in a robot overlay is an exit 2 naming it, before anything starts; the shipped one passes.
printf 'pilot:\n  max_range: 0.01\n' >"$tmp/bad_robot.yaml"
"$launch" "$src/deploy/hosts/pilot.yaml" --bin "$bin" --set "config=$src/deploy/config/lasonic.yaml" \
  --set "robot=$src/deploy/config/mobot4.yaml" --set "scenario=$src/deploy/scenarios/fig4_room.yaml" \
  --check >"$tmp/launch1h.txt" 2>&1 || die "--check of the shipped pilot profile: exit $?: $(cat "$tmp/launch1h.txt")"
rc=0
"$launch" "$src/deploy/hosts/pilot.yaml" --bin "$bin" --set "config=$src/deploy/config/lasonic.yaml" \
  --set "robot=$tmp/bad_robot.yaml" --set "scenario=$src/deploy/scenarios/fig4_room.yaml" \
  --check >"$tmp/launch1h.txt" 2>&1 || rc=$?
((rc == 2)) || die "--check with pilot.max_range 0.01: exit $rc, expected 2"
grep -q "lasonic-pilot: configuration not usable" "$tmp/launch1h.txt" &&
  grep -q "pilot.max_range" "$tmp/launch1h.txt" || die "the bad key is not named: $(cat "$tmp/launch1h.txt")"
! grep -q "lasonic-complement: configuration not usable" "$tmp/launch1h.txt" ||
  die "the complement blamed for the pilot's key: $(cat "$tmp/launch1h.txt")"
# --print-config: each process's configuration in effect, under the host's commands: the robot
# overlay's key names the overlay; a bad key is still an exit 2 naming it.
"$launch" "$src/deploy/hosts/pilot.yaml" --bin "$bin" --set "config=$src/deploy/config/lasonic.yaml" \
  --set "robot=$src/deploy/config/pioneer.yaml" --set "scenario=$src/deploy/scenarios/fig4_room.yaml" \
  --print-config >"$tmp/launch1p.txt" 2>&1 || die "--print-config of the pilot profile: exit $?: $(cat "$tmp/launch1p.txt")"
for p in lasonic-complement lasonic-pilot lasonic-sim-world; do
  grep -q "^# $p: the configuration in effect" "$tmp/launch1p.txt" || die "--print-config: no $p in: $(head -5 "$tmp/launch1p.txt")"
done
grep -qx "pilot.robot_radius: 0.27  # $src/deploy/config/pioneer.yaml" "$tmp/launch1p.txt" ||
  die "--print-config: the overlay's robot_radius is not named: $(grep robot_radius "$tmp/launch1p.txt")"
rc=0
"$launch" "$src/deploy/hosts/pilot.yaml" --bin "$bin" --set "config=$src/deploy/config/lasonic.yaml" \
  --set "robot=$tmp/bad_robot.yaml" --set "scenario=$src/deploy/scenarios/fig4_room.yaml" \
  --print-config >"$tmp/launch1q.txt" 2>&1 || rc=$?
((rc == 2)) && grep -q "pilot.max_range" "$tmp/launch1q.txt" ||
  die "--print-config with pilot.max_range 0.01: exit $rc, expected 2 naming the key: $(cat "$tmp/launch1q.txt")"
# --max-time and the profile's times: finite and at most 1e6 s (nan ran for ever, 1e300 stopped at once).
for t in nan inf 1e300 -1; do
  rc=0
  "$launch" "$tmp/missing.yaml" --log-dir "$tmp/logs1" --max-time "$t" >"$tmp/launch1f.txt" 2>&1 || rc=$?
  ((rc == 2)) || die "--max-time $t: exit $rc, expected 2"
  grep -q -- "--max-time" "$tmp/launch1f.txt" || die "--max-time $t: the option is not named: $(cat "$tmp/launch1f.txt")"
done
printf 'lcm_url: memq://\nprocesses:\n  - {name: p, command: [sleep, "5"], start_delay_s: 1e300}\n' >"$tmp/delay.yaml"
rc=0
"$launch" "$tmp/delay.yaml" --log-dir "$tmp/logs1" >"$tmp/launch1g.txt" 2>&1 || rc=$?
((rc == 2)) || die "start_delay_s: 1e300: exit $rc, expected 2"
grep -q "processes\[0\].start_delay_s: must be in" "$tmp/launch1g.txt" || die "start_delay_s is not named: $(cat "$tmp/launch1g.txt")"
echo "$test_name: (1) ok"

# 2. Restarts, back-off, kill -9, finish, stop order, SIGINT ignored.
cat >"$tmp/host.yaml" <<'YAML'
host: test
lcm_url: memq://
restart: {initial_delay_s: 0.2, max_delay_s: 0.8, reset_after_s: 30}
stop_timeout_s: 1
finish_grace_s: 0.2
processes:
  - {name: first, command: [sh, -c, 'trap "echo first got INT; exit 0" INT; while :; do sleep 0.05; done']}
  - {name: crasher, command: [sh, -c, 'echo crashing; exit 3'], restart: on-failure}
  - {name: stubborn, command: [sh, -c, 'trap "" INT; while :; do sleep 0.05; done']}
  - {name: victim, command: [sleep, "60"]}
  - {name: done, command: [sleep, "4"], restart: never, finish: true}
YAML
"$launch" "$tmp/host.yaml" --log-dir "$tmp/logs2" --max-time 30 2>"$tmp/launch2.txt" &
lpid=$!
pids+=("$lpid")
for _ in $(seq 50); do grep -q "victim started" "$tmp/launch2.txt" && break; sleep 0.1; done
victim=$(sed -n 's/.*victim started (pid \([0-9]*\)).*/\1/p' "$tmp/launch2.txt" | head -1)
[[ -n $victim ]] || die "victim was not started"
sleep 0.5
kill -9 "$victim"
t_kill=$(date +%s.%N)
for _ in $(seq 50); do grep -q "victim started.*restart 1" "$tmp/launch2.txt" && break; sleep 0.05; done
t_back=$(date +%s.%N)
grep -q "victim started.*restart 1" "$tmp/launch2.txt" || die "victim was not restarted after kill -9"
awk -v a="$t_kill" -v b="$t_back" 'BEGIN { printf "victim restarted %.2f s after kill -9\n", b - a }'
rc=0
wait "$lpid" || rc=$?
cat "$tmp/launch2.txt"
((rc == 0)) || die "the run ended by its finish process: exit $rc, expected 0"
grep -q "victim killed by signal 9" "$tmp/launch2.txt" || die "the kill -9 is not reported"
# Its lines carry the processes' time stamp (local date and time in microseconds), so that they
# interleave with the processes' own lines and line up with an LCM log's times.
stamp_re='^\[lasonic-launch [0-9]{4}-[0-9]{2}-[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{6}\] '
grep -Ev "$stamp_re" "$tmp/launch2.txt" | grep '^\[lasonic-launch ' &&
  die "lasonic-launch lines without a date and time in microseconds (above)"
grep -Eq "$stamp_re" "$tmp/launch2.txt" || die "no lasonic-launch line with a date and time in microseconds"
grep -q "victim.*restarting in 0.2 s" "$tmp/launch2.txt" || die "no 0.2 s restart delay after the first crash"
# The crasher: 0.2, 0.4, 0.8, 0.8 ... s
delays=$(sed -n 's/.*crasher exited with status 3 after .* restarting in \([0-9.]*\) s/\1/p' "$tmp/launch2.txt" | head -4 | tr '\n' ' ')
[[ $delays == "0.2 0.4 0.8 0.8 " ]] || die "crasher's back-off: '$delays', expected '0.2 0.4 0.8 0.8 '"
[[ $(grep -c '^\[lasonic-launch.*start' "$tmp/logs2/victim.txt") -eq 2 ]] || die "victim.txt does not show two starts"
grep -q crashing "$tmp/logs2/crasher.txt" || die "crasher's output is not in its log"
grep -q "first got INT" "$tmp/logs2/first.txt" || die "first was not stopped with SIGINT"
grep -q "stubborn (pid [0-9]*) ignored SIGINT for 1.0 s: killing it" "$tmp/launch2.txt" || die "stubborn was not killed"
# Reverse order: victim, stubborn, crasher, first.
order=$(sed -n 's/.*\] \([a-z]*\) stopped$/\1/p; s/.*\] \([a-z]*\) killed by signal 9 (Killed) on stopping/\1/p' "$tmp/launch2.txt" | tr '\n' ' ')
[[ $order == "victim stubborn first " ]] || die "stop order '$order', expected 'victim stubborn first ' (crasher between restarts)"
if pgrep -f 'while :; do sleep 0.05' >/dev/null 2>&1; then
  pgrep -af 'while :; do sleep 0.05' >&2
  die "processes left over after the run"
fi
echo "$test_name: (2) ok"

# 3. SIGTERM to the launcher.
cat >"$tmp/term.yaml" <<'YAML'
lcm_url: memq://
processes:
  - {name: a, command: [sleep, "60"]}
  - {name: b, command: [sleep, "61"]}
YAML
"$launch" "$tmp/term.yaml" --log-dir "$tmp/logs3" 2>"$tmp/launch3.txt" &
lpid=$!
for _ in $(seq 50); do grep -q "b started" "$tmp/launch3.txt" && break; sleep 0.1; done
a=$(sed -n 's/.*\] a started (pid \([0-9]*\)).*/\1/p' "$tmp/launch3.txt")
kill -TERM "$lpid"
rc=0
wait "$lpid" || rc=$?
((rc == 0)) || die "SIGTERM: exit $rc, expected 0"
! kill -0 "$a" 2>/dev/null || die "a (pid $a) still runs after the launcher stopped"
grep -q "signal received: stopping every process" "$tmp/launch3.txt" || die "no stop message"
echo "$test_name: (3) ok"

# 4. A process that exits 2 (bad command line or configuration) is not restarted, whatever its
# restart policy: the others run on, and the launcher exits 2 when the run ends.
cat >"$tmp/badconfig.yaml" <<'YAML'
lcm_url: memq://
restart: {initial_delay_s: 0.1, max_delay_s: 0.2, reset_after_s: 30}
processes:
  - {name: misconfigured, command: [sh, -c, 'echo "x.yaml: pilto: unknown key" >&2; exit 2'], restart: always}
  - {name: done, command: [sleep, "1.5"], restart: never, finish: true}
YAML
rc=0
"$launch" "$tmp/badconfig.yaml" --log-dir "$tmp/logs4" --max-time 20 2>"$tmp/launch4.txt" || rc=$?
((rc == 2)) || die "a process exiting 2: the launcher exited $rc, expected 2"
starts=$(grep -c "misconfigured started" "$tmp/launch4.txt" || true)
((starts == 1)) || die "a process exiting 2 was started $starts times, expected once"
grep -q "misconfigured exited 2 (bad command line or configuration: see .*misconfigured.txt) after .* s: not restarted" \
  "$tmp/launch4.txt" || die "no 'not restarted' message: $(cat "$tmp/launch4.txt")"
# ... also a `finish` process: the run ends (exit 2), it does not wait for --max-time.
cat >"$tmp/badfinish.yaml" <<'YAML'
lcm_url: memq://
processes:
  - {name: other, command: [sleep, "30"]}
  - {name: world, command: [sh, -c, 'exit 2'], restart: on-failure, finish: true}
YAML
rc=0
"$launch" "$tmp/badfinish.yaml" --log-dir "$tmp/logs4b" --max-time 20 2>"$tmp/launch4b.txt" || rc=$?
((rc == 2)) || die "a finish process exiting 2: the launcher exited $rc, expected 2: $(cat "$tmp/launch4b.txt")"
grep -q "world has finished" "$tmp/launch4b.txt" || die "a finish process exiting 2 did not end the run"
echo "$test_name: (4) ok"
echo "$test_name: PASS"
