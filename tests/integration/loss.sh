#!/usr/bin/env bash
# loss.sh: 20 % message loss, injected at the message level (this kernel has no netem). Run it
# inside a private network namespace (ctest does). Env: LASONIC_BIN, LASONIC_SOURCE.
# lasonic-sim-world and the two drivers publish on URL S (port 7667). Two lasonic-lossy-relays copy
# everything to URL L0 (port 7668, loss 0) and URL L20 (port 7669, 20 % of the robot's channels
# dropped, seeded; the truth passes), each with its own lasonic-complement + lasonic-pilot +
# lasonic-navigator and lcm-logger: both pipelines see the same sensor stream, one of them with
# losses. lasonic-eval scores both logs: the lossy pipeline must keep running without errors other
# than the ones loss causes, and its sector-map missed rate may exceed the lossless one by at most
# 0.02. The tactical AGM under loss against the lossless one (lasonic-fault-check nearest: each
# lossy map against the lossless one at or before it): measured, and the lossy navigator must keep
# publishing at its 2 Hz.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
die_globs+=('*.txt')
dur=${LASONIC_LOSS_DURATION:-15}
base='udpm://239.255.76.67:PORT?ttl=0&recv_buf_size=4194304'
s_url=${base/PORT/7667}
declare -A urls=([0]=${base/PORT/7668} [20]=${base/PORT/7669})

for loss in 0 20; do
  u=${urls[$loss]}
  lcm-logger --lcm-url="$u" --invert-channels --channel=LCM_SELF_TEST "$tmp/l$loss.lcmlog" >"$tmp/logger$loss.txt" 2>&1 &
  pids+=("$!")
  eval "logger$loss=\$!"
  start "complement$loss" "$bin/lasonic-complement" --config "$config" --lcm-url "$u"
  start "pilot$loss" "$bin/lasonic-pilot" --config "$config" --lcm-url "$u"
  start "navigator$loss" "$bin/lasonic-navigator" --config "$config" --lcm-url "$u"
  "$bin/lasonic-lossy-relay" --from "$s_url" --to "$u" --loss "0.$loss" --seed 1 >"$tmp/relay$loss.txt" 2>&1 &
  pids+=("$!")
  eval "relay$loss=\$!"
done
start laser "$bin/lasonic-laser-driver" --config "$config" --scenario "$scenario" --lcm-url "$s_url"
start sonar "$bin/lasonic-sonar-driver" --config "$config" --scenario "$scenario" --lcm-url "$s_url"
wait_ready laser sonar complement0 pilot0 navigator0 complement20 pilot20 navigator20
sleep 0.5  # the relays (no start-up message) and the loggers
"$bin/lasonic-sim-world" --config "$config" --scenario "$scenario" --lcm-url "$s_url" --duration "$dur" \
  2>"$tmp/world.err" >&2 || die "lasonic-sim-world failed"
sleep 1
for loss in 0 20; do
  r=relay$loss
  kill -INT "${!r}"
  wait "${!r}" || true
done
sleep 0.3
for loss in 0 20; do
  l=logger$loss
  kill -INT "${!l}"
  wait "${!l}" || true
done
echo "relay, 20 %:"
cat "$tmp/relay20.txt"
dropped=$(awk '$1 == "SONAR_RING" {print $4}' "$tmp/relay20.txt")
passed=$(awk '$1 == "SONAR_RING" {print $2}' "$tmp/relay20.txt")
awk -v d="$dropped" -v p="$passed" 'BEGIN { r = d / (d + p); exit !(r > 0.15 && r < 0.25) }' ||
  die "the relay dropped $dropped of $((dropped + passed)) SONAR_RING, not about 20 %"

key() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['sector_map'][sys.argv[2]])" "$1" "$2"; }
for loss in 0 20; do
  "$bin/lasonic-eval" --log "$tmp/l$loss.lcmlog" --scenario "$scenario" --json "$tmp/e$loss.json" >/dev/null ||
    die "lasonic-eval failed on the ${loss} % log"
  "$bin/lasonic-log-stats" "$tmp/l$loss.lcmlog" >"$tmp/stats$loss"
done
m0=$(key "$tmp/e0.json" missed_rate); m20=$(key "$tmp/e20.json" missed_rate)
f0=$(key "$tmp/e0.json" false_alarm_rate); f20=$(key "$tmp/e20.json" false_alarm_rate)
n0=$(key "$tmp/e0.json" maps); n20=$(key "$tmp/e20.json" maps)
echo "loss 0 %: SECTOR_MAP $n0 maps, missed_rate $m0, false_alarm_rate $f0"
echo "loss 20 %: SECTOR_MAP $n20 maps, missed_rate $m20, false_alarm_rate $f20"
awk -v a="$n0" -v b="$n20" 'BEGIN { exit !(a > 0 && b > 0.7 * a) }' || die "too few SECTOR_MAP under loss"
awk -v a="$m0" -v b="$m20" 'BEGIN { exit !(b <= a + 0.02) }' || die "missed rate under 20 % loss $m20 > lossless $m0 + 0.02"
# The tactical level under loss: a lost firing group is one update cycle fewer, so a surface
# collects fewer hits toward G_T (5) and some cells at its edge stay below it.
"$bin/lasonic-fault-check" nearest "$tmp/l20.lcmlog" "$tmp/l0.lcmlog" AGM_TACTICAL >"$tmp/tactical.txt"
t() { awk -v k="$1" '$1 == k {print $2}' "$tmp/tactical.txt"; }
own=$(awk '$1 == "series" { o += $3; c += $5 } END { printf "%.3f", o ? c / o : 0 }' "$tmp/tactical.txt")
echo "loss 20 %: AGM_TACTICAL $(t maps_a) maps (lossless $(t maps_b)); of the lossless map's occupied cells it holds" \
  "$(t b_in_a), of its own $own are in the lossless map"
awk -v a="$(t maps_b)" -v b="$(t maps_a)" 'BEGIN { exit !(a >= 20 && b >= 0.9 * a) }' ||
  die "the navigator under loss published $(t maps_a) tactical maps, the lossless one $(t maps_b)"
# Loss may cost scans their odometry (rejected.laser_no_odometry) but nothing may fail otherwise.
for loss in 0 20; do
  for p in lasonic-complement lasonic-pilot lasonic-navigator; do
    grep -E "^$p\.(decode_errors|handler_failures|publish_failures|oversize)" "$tmp/stats$loss" &&
      die "$p reported failures under ${loss} % loss"
  done
done
for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null || true; done
echo "$test_name: PASS"
