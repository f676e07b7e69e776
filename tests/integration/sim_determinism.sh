#!/usr/bin/env bash
# sim_determinism.sh: lasonic-sim is deterministic: the same scenario and seed give a byte-identical
# log, another seed another log; in both sensor profiles (physical, the default, and ideal), which
# differ; --robot-speed drives the same scene at another speed (another log, ending later at a lower
# speed), and with --same-path for as long as the same path takes (duration_s x scene speed / new
# speed). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
set -euo pipefail
bin=${LASONIC_BIN:?set LASONIC_BIN}
src=${LASONIC_SOURCE:?set LASONIC_SOURCE}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sim() { "$bin/lasonic-sim" --scenario "$src/deploy/scenarios/fig4_room.yaml" --duration 8 "$@"; }
sim --out "$tmp/a.lcmlog"
sim --out "$tmp/b.lcmlog" --config "$src/deploy/config/lasonic.yaml"
sim --out "$tmp/c.lcmlog" --seed 5
sim --out "$tmp/d.lcmlog" --profile ideal
sim --out "$tmp/e.lcmlog" --profile ideal
sim --out "$tmp/f.lcmlog" --profile ideal --seed 5
sim --out "$tmp/g.lcmlog" --robot-speed 0.3  # the scene's own speed
sim --out "$tmp/h.lcmlog" --robot-speed 0.6
fail() { echo "sim_determinism.sh: FAIL: $*" >&2; exit 1; }
cmp "$tmp/a.lcmlog" "$tmp/b.lcmlog" || fail "same seed, different logs"
cmp "$tmp/d.lcmlog" "$tmp/e.lcmlog" || fail "same seed, different logs (ideal profile)"
cmp -s "$tmp/a.lcmlog" "$tmp/c.lcmlog" && fail "another seed gave the same log"
cmp -s "$tmp/d.lcmlog" "$tmp/f.lcmlog" && fail "another seed gave the same log (ideal profile)"
cmp -s "$tmp/a.lcmlog" "$tmp/d.lcmlog" && fail "the physical and ideal profiles gave the same log"
grep -q "^  speed: 0.3$" "$src/deploy/scenarios/fig4_room.yaml" || fail "fig4_room's robot speed is no longer 0.3: update this test"
cmp "$tmp/a.lcmlog" "$tmp/g.lcmlog" || fail "--robot-speed at the scene's own speed changed the log"
cmp -s "$tmp/a.lcmlog" "$tmp/h.lcmlog" && fail "--robot-speed 0.6 gave the same log"
# The same path at twice the speed: half the scene's duration_s (a span of whole SIM_STATE periods).
scene_s=$(awk '$1 == "duration_s:" {print $2}' "$src/deploy/scenarios/fig4_room.yaml")
"$bin/lasonic-sim" --scenario "$src/deploy/scenarios/fig4_room.yaml" --out "$tmp/i.lcmlog" --robot-speed 0.6 --same-path
span=$("$bin/lasonic-log-stats" "$tmp/i.lcmlog" | awk '$1 == "span_s" {print $2}')
awk -v s="$span" -v d="$scene_s" 'BEGIN { exit !(s > d / 2 - 0.1 && s <= d / 2 + 0.01) }' ||
  fail "--robot-speed 0.6 --same-path simulated $span s, not half of fig4_room's $scene_s s"
if "$bin/lasonic-sim" --scenario "$src/deploy/scenarios/fig4_room.yaml" --out "$tmp/j.lcmlog" --same-path 2>/dev/null; then
  fail "--same-path without --robot-speed was accepted"
fi
echo "sim_determinism.sh: PASS"
