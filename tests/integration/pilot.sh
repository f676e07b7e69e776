#!/usr/bin/env bash
# pilot.sh: integration test of lasonic-pilot over real LCM. Run it inside a private network
# namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
#  1. --help works; a bad config exits 2 naming the key; the shipped config starts cleanly;
#     --print-config lists each parameter with the layer that set it (a robot's overlay, the
#     shipped file, or the code's default), joins no LCM group and exits 0;
#  2. the pilot, fed a scripted input by lasonic-pilot-fixture (odometry, a laser scan, 34 firing
#     groups, garbage and bad readings), publishes SECTOR_MAP per input and AGM_OPERATIONAL at
#     2 Hz with the hand-computed values, counts the bad input, keeps running, exits 0 on SIGTERM;
#     its start-up log line names the build (--version's line) and its configuration file.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
url+='&recv_buf_size=4194304'

# 1. Command line and configuration.
"$bin/lasonic-pilot" --help >"$tmp/help.out" || die "--help failed"
grep -q -- '--lcm-url' "$tmp/help.out" || die "--help does not mention --lcm-url"
printf 'pilot:\n  agm: {t: -1}\n' >"$tmp/bad.yaml"
expect_bad_config pilot.agm.t pilot.agm.t "$bin/lasonic-pilot" --config "$tmp/bad.yaml"
rc=0
timeout --preserve-status -s TERM -k 20 1 "$bin/lasonic-pilot" --config "$config" \
  --lcm-url "$url" 2>"$tmp/shipped.err" >&2 || rc=$?
[[ $rc -eq 0 ]] || die "the shipped config: exit status $rc, expected 0 after SIGTERM"

# --print-config over the shipped file and the Pioneer overlay: the overlay's robot_radius, the
# shipped file's sectors, and a key no file sets (the code's default); no --lcm-url is needed.
robot=$src/deploy/config/pioneer.yaml
"$bin/lasonic-pilot" --config "$config" --config "$robot" --print-config >"$tmp/print.out" 2>"$tmp/print.err" ||
  die "--print-config: exit $?: $(cat "$tmp/print.err")"
grep -qx "pilot.robot_radius: 0.27  # $robot" "$tmp/print.out" ||
  die "--print-config: no pilot.robot_radius from $robot in: $(grep robot_radius "$tmp/print.out")"
grep -qx "pilot.sectors: 48  # $config" "$tmp/print.out" ||
  die "--print-config: no pilot.sectors from $config in: $(grep 'pilot.sectors' "$tmp/print.out")"
grep -Eq '^pilot\.[a-z_.]+: .*  # default$' "$tmp/print.out" || die "--print-config: no key at its default"
! grep -v '^#' "$tmp/print.out" | grep -Ev '^[a-z_]+(\.[a-z_0-9]+|\[[0-9]+\])+: .+  # .+$' >"$tmp/print_odd.out" ||
  die "--print-config: lines not of the form 'key.path: value  # source': $(head -3 "$tmp/print_odd.out")"
rc=0
"$bin/lasonic-pilot" --config "$tmp/bad.yaml" --print-config >/dev/null 2>"$tmp/print_bad.err" || rc=$?
[[ $rc -eq 2 ]] && grep -q 'pilot.agm.t' "$tmp/print_bad.err" ||
  die "--print-config with a bad config: exit $rc, expected 2 naming pilot.agm.t: $(cat "$tmp/print_bad.err")"

echo "$test_name: (1) ok: --help, a bad config, the shipped config, --print-config"

# 2. A live run with explicit parameters (the checks are hand-computed from them).
cat >"$tmp/pilot.yaml" <<'YAML'
pilot:
  agm: {size: 100, cell_size: 0.10, g_max: 100, h_max: 12, t: 1, g_threshold: 2}
  robot_radius: 0.35
  max_range: 3.0
  gp_threshold: 2
  laser_stale_s: 0.5
  sonar_stale_s: 0.5
  agm_publish_hz: 2
  sonar_cell_point: nearest     # the cell's point nearest the robot: exact cell boundaries
  remembered: false             # no navigator here
YAML
start_logger run.lcmlog
start pilot "$bin/lasonic-pilot" --config "$tmp/pilot.yaml" --lcm-url "$url"
pilot=$!
wait_ready pilot
# Its first log line names the build and the configuration files (README "Processes: start-up,
# exit codes, status").
grep -Eq "\] lasonic [0-9]+\.[0-9]+\.[0-9]+ \((git [0-9a-f]+|unknown).*\); configuration $tmp/pilot.yaml$" \
  "$tmp/pilot.err" || die "no start-up line naming the build and $tmp/pilot.yaml in: $(head -3 "$tmp/pilot.err")"

"$bin/lasonic-pilot-fixture" feed "$url" || die "feeding the pilot failed"
echo "$test_name: (2) fed"
sleep 1.5  # at least one heartbeat after the input
kill -0 "$pilot" 2>/dev/null || die "the pilot died during the run"
expect_term_exit "$pilot" pilot
sleep 0.3
stop_logger

"$bin/lasonic-pilot-fixture" check "$tmp/run.lcmlog" 2>"$tmp/check.err" || die "log check: $(cat "$tmp/check.err")"
echo "$test_name: PASS"
