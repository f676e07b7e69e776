#!/usr/bin/env bash
# latency.sh LOG SPEED MIN_GROUPS [SAMPLES]: the live pipeline's SONAR_RING -> SECTOR_MAP latency.
# Starts lasonic-complement, lasonic-pilot and lasonic-navigator (shipped configuration) on LCM,
# plays LOG's sensor channels into them at SPEED x real time with lasonic-latency and prints its
# line. MUST run inside a private network namespace: `tests/netns/in-netns.sh latency.sh ...`
# (./run bench and the smoke test do). Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository);
# LASONIC_LATENCY_RT=1: the processes and the probe run with real-time priority (SCHED_FIFO 20,
# `chrt`), as a robot's computer would run its control path; this shows how much of the tail is
# waiting for a CPU that other programs hold.
set -euo pipefail
log=$1 speed=$2 min_groups=$3 samples=${4:-}
# bin, src, config, tmp and pids (killed on exit), as the integration tests have them.
source "$(dirname "$0")/../integration/lib.sh"
url+='&recv_buf_size=4194304'
# Inside the namespace only: lo must be the sole interface that is up.
if ip -o link show up | grep -qv ' lo:'; then
  echo "latency.sh: refusing to run outside a private network namespace (use tests/netns/in-netns.sh)" >&2
  exit 2
fi
rt=()
if [[ ${LASONIC_LATENCY_RT:-0} == 1 ]]; then
  chrt -f 20 true 2>/dev/null || { echo "latency.sh: SCHED_FIFO not permitted here" >&2; exit 77; }
  rt=(chrt -f 20)
fi
for p in complement pilot navigator; do
  "${rt[@]}" "$bin/lasonic-$p" --config "$config" --lcm-url "$url" >"$tmp/$p.err" 2>&1 &
  pids+=("$!")
done
sleep 1
rc=0
"${rt[@]}" "$bin/lasonic-latency" --in "$log" --lcm-url "$url" --speed "$speed" --min-groups "$min_groups" \
  ${samples:+--samples "$samples"} || rc=$?
if [[ $rc -ne 0 ]]; then
  for p in complement pilot navigator; do echo "--- lasonic-$p" >&2; tail -5 "$tmp/$p.err" >&2; done
fi
exit "$rc"
