#!/usr/bin/env bash
# complement.sh: integration test of lasonic-complement over real LCM. Run it inside a private
# network namespace (tests/netns/in-netns.sh; ctest does). Env: LASONIC_BIN (build/bin),
# LASONIC_SOURCE (repository root).
#  1. a bad config exits 2 naming the key;
#  2. the process, fed the paper's Fig. 4 fixture (lasonic-complement-check publish), publishes
#     RADAR_MAP, SONAR_HYPOTHESIS and SONAR_COMPLEMENT with the expected classes and counts them
#     (and the rejected NaN) in PROCESS_STATUS; it keeps running and exits 0 on SIGTERM.
set -euo pipefail

bin=${LASONIC_BIN:?set LASONIC_BIN}
src=${LASONIC_SOURCE:?set LASONIC_SOURCE}
url='udpm://239.255.76.67:7667?ttl=0'
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT
die() {
  echo "complement.sh: FAIL: $*" >&2
  for f in "$tmp"/*.err; do [[ -f $f ]] && { echo "--- $f" >&2; tail -20 "$f" >&2; }; done
  exit 1
}

# 1. Config errors name the key and exit 2.
printf 'complement:\n  tolerence: 0.2\n' >"$tmp/bad.yaml"
rc=0
"$bin/lasonic-complement" --config "$tmp/bad.yaml" --lcm-url "$url" 2>"$tmp/bad.err" >&2 || rc=$?
[[ $rc -eq 2 ]] || die "bad config: exit status $rc, expected 2"
grep -q 'complement.tolerence' "$tmp/bad.err" || die "bad config: error does not name complement.tolerence"

# 2. A live run with the shipped configuration.
lcm-logger --lcm-url="$url" "$tmp/run.lcmlog" >"$tmp/logger.err" 2>&1 &
pids+=($!)
"$bin/lasonic-complement" --config "$src/deploy/config/lasonic.yaml" --lcm-url "$url" 2>"$tmp/complement.err" >&2 &
proc=$!
pids+=("$proc")
sleep 1  # subscriptions up
"$bin/lasonic-complement-check" publish "$url" || die "publishing the fixture failed"
sleep 1.5  # at least one heartbeat after the input
kill -0 "$proc" 2>/dev/null || die "lasonic-complement died"
kill -TERM "$proc"
rc=0
wait "$proc" || rc=$?
[[ $rc -eq 0 ]] || die "exit status $rc after SIGTERM, expected 0"
sleep 0.3
kill -INT "${pids[0]}"
wait "${pids[0]}" || true

"$bin/lasonic-complement-check" log "$tmp/run.lcmlog" 2>"$tmp/check.err" || die "$(cat "$tmp/check.err")"
echo "complement.sh: PASS"
