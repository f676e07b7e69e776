#!/usr/bin/env bash
# outage.sh: the laser lost for 3 s on the move (README "Faults, loss and bad input", *A laser lost
# on the move*), on the offline pipeline (no network). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE.
#  1. lasonic-lossy-relay --outage drops every LASER_SCAN from 4 s to 7 s after the log's first
#     message and nothing else: 15 scans of 5 Hz, the longest gap between scans 3.2 s.
#  2. Replayed with the shipped configuration (pilot.stale_values: held_min): the complement and
#     the pilot each report the outage once (laser.lost) and its end ("back after 3.200 s"); the
#     sector map flags the laser stale within two scan periods (+ 0.12 s) and no stale map reports
#     more free space in any sector than the last fresh one (lasonic-fault-check stale).
#  3. With stale_values: moved the same outage is flagged and reported alike, and the stale maps
#     do report more free space somewhere (the robot drives on, the last scan moves with it): the
#     key changes what a stale map holds. With stale_values: frontier (the moved scan and the
#     edges of what it saw free) fewer stale maps than moved's report more free space, and in every
#     stale map each sector's laser distance is moved's or nearer, and some are nearer.
#  4. Bad --outage values exit 2 naming the option.
set -euo pipefail
source "$(dirname "$0")/lib.sh"

"$bin/lasonic-sim" --scenario "$scenario" --duration 12 --out "$tmp/raw.lcmlog" >"$tmp/sim.err" 2>&1 ||
  die "lasonic-sim failed"
"$bin/lasonic-lossy-relay" --in-log "$tmp/raw.lcmlog" --out-log "$tmp/cut.lcmlog" --lossy LASER_SCAN \
  --outage 4:7 >"$tmp/relay.txt" 2>"$tmp/relay.err" || die "lasonic-lossy-relay --outage failed"
grep -qx "LASER_SCAN 45 passed 15 dropped" "$tmp/relay.txt" || die "relay: $(grep LASER_SCAN "$tmp/relay.txt")"
grep -qx "ODOMETRY 601 passed 0 dropped" "$tmp/relay.txt" || die "relay dropped odometry: $(cat "$tmp/relay.txt")"
"$bin/lasonic-log-stats" "$tmp/cut.lcmlog" >"$tmp/stats"
gap=$(stat LASER_SCAN.max_gap_s)
[[ $gap == 3.200 ]] || die "the longest gap between scans is $gap s, expected 3.200"
first=$(stat first_us)
t_stop=$((first + 4000000)) t_resume=$((first + 7000000))

# replay NAME [CONFIG...]: the whole pipeline over the cut log -> $tmp/NAME.out, its status
replay() {
  local name=$1
  shift
  local cfg=(--config "$config")
  for c in "$@"; do cfg+=(--config "$c"); done
  "$bin/lasonic-replay" --in "$tmp/cut.lcmlog" --out "$tmp/$name.out" "${cfg[@]}" --status \
    >"$tmp/$name.status" 2>"$tmp/$name-replay.err" || die "$name: lasonic-replay failed"
  local p
  for p in lasonic-complement lasonic-pilot; do
    grep -qx "$p laser.lost 1" "$tmp/$name.status" || die "$name: $p did not count the outage once"
  done
  [[ $(grep -c "LASER_SCAN back after 3.200 s without" "$tmp/$name-replay.err") -eq 2 ]] ||
    die "$name: the outage's end was not logged by both the complement and the pilot"
}

replay held
"$bin/lasonic-fault-check" stale "$tmp/held.out" "$t_stop" "$t_resume" laser >"$tmp/held.stale" 2>"$tmp/held-stale.err" ||
  die "held_min: not flagged stale, or a stale map freer than the last fresh one: $(cat "$tmp/held.stale")"
age=$(awk '$1 == "stale_age_s" {print $2}' "$tmp/held.stale")
awk -v a="$age" 'BEGIN { exit !(a > 0 && a <= 0.52) }' || die "held_min: flagged stale at an age of $age s"
grep -q "holds the laser's last distances" "$tmp/held-replay.err" || die "held_min: the outage's message"

# stale_rule RULE: the replay with pilot.stale_values: RULE -> $tmp/RULE.out, and its stale maps
# (lasonic-fault-check stale) in $tmp/RULE.stale: exit status in stale_rc, maps_freer in stale_freer.
stale_rule() {
  printf 'pilot:\n  stale_values: %s\n' "$1" >"$tmp/$1.yaml"
  replay "$1" "$tmp/$1.yaml"
  stale_rc=0
  "$bin/lasonic-fault-check" stale "$tmp/$1.out" "$t_stop" "$t_resume" laser >"$tmp/$1.stale" 2>/dev/null || stale_rc=$?
  stale_freer=$(awk '$1 == "maps_freer" {print $2}' "$tmp/$1.stale")
}
flagged() { [[ $(awk '$1 == "stale_flagged" {print $2}' "$tmp/$1.stale") == 1 ]]; }

stale_rule moved
freer=$stale_freer
[[ $stale_rc -eq 1 ]] && flagged moved && [[ ${freer:-0} -gt 0 ]] ||
  die "moved: expected flagged stale maps freer than the last fresh one: $(cat "$tmp/moved.stale")"
grep -q "moves the laser's last scan with odometry" "$tmp/moved-replay.err" || die "moved: the outage's message"

# frontier: the moved scan and where it did not see free. Its laser distances are those of moved
# or nearer (the shadows' edges), so fewer of its stale maps are freer.
stale_rule frontier
frontier_freer=$stale_freer
flagged frontier && [[ ${frontier_freer:-0} -lt $freer ]] ||
  die "frontier: expected flagged stale maps, fewer of them freer than moved's $freer: $(cat "$tmp/frontier.stale")"
"$bin/lasonic-fault-check" laser-nearer "$tmp/frontier.out" "$tmp/moved.out" "$t_stop" "$((t_resume + 1000000))" \
  >"$tmp/nearer.txt" 2>&1 || die "frontier: a stale laser distance farther than moved's, or none nearer: $(cat "$tmp/nearer.txt")"
grep -q "moves the laser's last scan, and where it did not see free, with odometry" "$tmp/frontier-replay.err" ||
  die "frontier: the outage's message"

for bad in 7:4 x:3 -1:2 3 4:4; do
  rc=0
  "$bin/lasonic-lossy-relay" --in-log "$tmp/raw.lcmlog" --out-log "$tmp/bad.lcmlog" --outage "$bad" \
    >/dev/null 2>"$tmp/bad.txt" || rc=$?
  [[ $rc -eq 2 ]] && grep -qF -- "--outage" "$tmp/bad.txt" ||
    die "--outage $bad: exit status $rc: $(cat "$tmp/bad.txt")"
done
echo "$test_name: PASS (held_min: $(tr '\n' ' ' <"$tmp/held.stale"); moved: $freer stale maps freer; frontier: $frontier_freer, $(tr '\n' ' ' <"$tmp/nearer.txt"))"
