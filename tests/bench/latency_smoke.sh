#!/usr/bin/env bash
# latency_smoke.sh: the latency probe of ./run bench works (run inside a private network namespace
# by ctest): 5 s of fig7_lab (about 147 firing groups) played at 2x real time into the live
# complement, pilot and navigator; lasonic-latency must match at least 144 groups to their
# SECTOR_MAPs by the maps' sonar time (it fails if the pipeline makes no maps, drops groups, or
# makes maps of other times) and print p50/p99/max. Every group is matched when nothing is lost;
# matching by publish time instead of sonar time matched about 133, which this bound rejects.
set -euo pipefail
source "$(dirname "$0")/../integration/lib.sh"
"$bin/lasonic-sim" --scenario "$scenario" --duration 5 --out "$tmp/in.lcmlog" >/dev/null 2>&1 || die "lasonic-sim failed"
line=$("$src/tests/bench/latency.sh" "$tmp/in.lcmlog" 2 144) || die "latency probe failed: ${line:-}"
echo "$test_name: $line"
[[ $line =~ ^groups\ [0-9]+\ matched\ [0-9]+\ p50_ms\ [0-9.]+\ p99_ms\ [0-9.]+\ max_ms\ [0-9.]+$ ]] ||
  die "unexpected output: $line"
echo "$test_name: PASS"
