#!/usr/bin/env bash
# run_bench.sh: the benchmark table of ./run bench (README "Performance"). Prints one Markdown
# table to stdout (and writes it to $OUT_DIR/bench-<UTC time>.md):
#   1. Google Benchmark per stage (build/bench/bench_*): median [min-max] over repetitions;
#   2. offline real-time factor of lasonic-replay per shipped scene (log reading and writing
#      included; its default threads, and fig7_lab also with --threads 1): median [min-max] over runs;
#   3. SONAR_RING -> SECTOR_MAP latency across the live processes over LCM, in a private network
#      namespace (latency.sh): p50 / p99 / max over >= LASONIC_BENCH_GROUPS firing groups;
#   4. the scale case (scale.yaml): fraction of one core lasonic-replay needs for real time.
# Env: LASONIC_BIN, LASONIC_SOURCE (required); LASONIC_BENCH_DIR (build/bench);
# LASONIC_BENCH_RUNS (5), LASONIC_BENCH_GROUPS (10000), LASONIC_BENCH_SPEED (4: the latency
# log is played at 4x real time), OUT_DIR (logs/bench).
set -euo pipefail
bin=${LASONIC_BIN:?set LASONIC_BIN}
src=${LASONIC_SOURCE:?set LASONIC_SOURCE}
bench_dir=${LASONIC_BENCH_DIR:-$(dirname "$bin")/bench}
runs=${LASONIC_BENCH_RUNS:-5}
groups=${LASONIC_BENCH_GROUPS:-10000}
speed=${LASONIC_BENCH_SPEED:-4}
out_dir=${OUT_DIR:-$src/logs/bench}
config=$src/deploy/config/lasonic.yaml
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out_dir"
say() { printf '[bench] %s\n' "$*" >&2; }

# stats: numbers on stdin -> "median [min-max]" (printf format $1)
stats() {
  sort -g | awk -v f="$1" '{v[NR]=$1} END {if (NR==0) {print "-"; exit}
    m = (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2
    printf(f " [" f "-" f "]\n", m, v[1], v[NR])}'
}

rows=()
row() { rows+=("| $1 | $2 | $3 |"); }

# ---- 1. per stage (JSON: the CSV reporter rejects benchmarks with differing counters)
for b in "$bench_dir"/bench_*; do
  [[ -x $b ]] || continue
  say "$(basename "$b")"
  "$b" --benchmark_repetitions="$runs" --benchmark_out="$tmp/gb.json" --benchmark_out_format=json >/dev/null 2>&1 || true
  # One "name cpu_time unit" line per repetition (run_type iteration), times in microseconds.
  awk -F': ' '
    /"name":/ {n=$2; gsub(/[",]/, "", n)}
    /"run_type":/ {it = ($2 ~ /iteration/)}
    /"cpu_time":/ {t=$2; gsub(/,/, "", t)}
    /"time_unit":/ {u=$2; gsub(/[",]/, "", u); if (it) {f = (u=="ns") ? 1e-3 : (u=="ms") ? 1e3 : (u=="s") ? 1e6 : 1; print n, t * f}}
    /"us_per_group":/ {v=$2; gsub(/,/, "", v); if (it) print n "(per_firing_group)", v * 1e6}
  ' "$tmp/gb.json" >"$tmp/gb.txt"
  for name in $(awk '{print $1}' "$tmp/gb.txt" | sort -u); do
    val=$(awk -v n="$name" '$1==n {print $2}' "$tmp/gb.txt" | stats '%.3g')
    row "stage: $(basename "$b" | sed 's/^bench_//') $name" "$val µs" "CPU time per iteration, $runs repetitions"
  done
done

# ---- 2. offline real-time factor per scene
for sc in "$src"/deploy/scenarios/*.yaml; do
  name=$(basename "$sc" .yaml)
  say "replay $name"
  "$bin/lasonic-sim" --scenario "$sc" --out "$tmp/$name.lcmlog" >/dev/null 2>&1
  for ((i = 0; i < runs; i++)); do
    "$bin/lasonic-replay" --in "$tmp/$name.lcmlog" --out "$tmp/out.lcmlog" --config "$config" 2>&1 >/dev/null |
      sed -n 's/.*s of log in .* real-time factor \([0-9.]*\),.*/\1/p'
  done | stats '%.0f' >"$tmp/rtf"
  dur=$("$bin/lasonic-replay" --in "$tmp/$name.lcmlog" --out "$tmp/out.lcmlog" --config "$config" 2>&1 >/dev/null |
    sed -n 's/.*: \([0-9.]*\) s of log in.*/\1/p')
  row "offline real-time factor: $name ($dur s)" "$(cat "$tmp/rtf") x" "lasonic-replay, log reading and writing included, $runs runs"
  if [[ $name == fig7_lab ]]; then  # the same on one thread (the stages' threads' share of the factor)
    for ((i = 0; i < runs; i++)); do
      "$bin/lasonic-replay" --threads 1 --in "$tmp/$name.lcmlog" --out "$tmp/out.lcmlog" --config "$config" 2>&1 >/dev/null |
        sed -n 's/.*s of log in .* real-time factor \([0-9.]*\),.*/\1/p'
    done | stats '%.0f' >"$tmp/rtf1"
    row "offline real-time factor: $name ($dur s), --threads 1" "$(cat "$tmp/rtf1") x" "as above, every stage on one thread (the log writer on its own)"
  fi
done

# ---- 3. live latency
per_s=$(awk 'BEGIN{print 1767/60}')  # fig7_lab: firing groups per simulated second
dur=$(awk -v g="$groups" -v r="$per_s" 'BEGIN{printf("%d", g / r * 1.12 + 5)}')
say "latency: $dur s of fig7_lab at ${speed}x in a private network namespace"
"$bin/lasonic-sim" --scenario "$src/deploy/scenarios/fig7_lab.yaml" --duration "$dur" --out "$tmp/long.lcmlog" >/dev/null 2>&1
latency() {  # LABEL [ENV...]: one latency row
  local label=$1 line n m p50 p99 pmax load_before
  shift
  load_before=$(cut -d' ' -f1 /proc/loadavg)
  if line=$("$src/tests/netns/in-netns.sh" env LASONIC_BIN="$bin" LASONIC_SOURCE="$src" "$@" \
    "$src/tests/bench/latency.sh" "$tmp/long.lcmlog" "$speed" "$groups"); then
    read -r _ n _ m _ p50 _ p99 _ pmax <<<"$line"
    row "SONAR_RING -> SECTOR_MAP, live$label (p50 / p99 / max)" "$p50 / $p99 / $pmax ms" \
      "$m of $n firing groups matched; complement, pilot, navigator over LCM; log played at ${speed}x; load average $load_before -> $(cut -d' ' -f1 /proc/loadavg) on $(nproc) cores"
  else
    row "SONAR_RING -> SECTOR_MAP, live$label" "failed" "${line:-see stderr}"
  fi
}
latency ""
say "latency again with real-time priority (SCHED_FIFO)"
latency ", SCHED_FIFO" LASONIC_LATENCY_RT=1

# ---- 4. scale case
say "scale case"
"$bin/lasonic-sim" --scenario "$src/deploy/scenarios/fig7_lab.yaml" --config "$config" --config "$src/tests/bench/scale.yaml" \
  --duration 20 --out "$tmp/scale.lcmlog" >/dev/null 2>&1
for ((i = 0; i < 3; i++)); do
  /usr/bin/time -f '%U %S' -o "$tmp/time" "$bin/lasonic-replay" --in "$tmp/scale.lcmlog" --out "$tmp/scale_out.lcmlog" \
    --config "$config" --config "$src/tests/bench/scale.yaml" >/dev/null 2>&1
  awk '{print ($1 + $2) / 20}' "$tmp/time"
done | stats '%.2f' >"$tmp/scale"
rm -f "$tmp/scale_out.lcmlog"
row "scale: 1000x1000 AGM at 5 cm, 1080-beam laser at 40 Hz, 24 sonars" "$(cat "$tmp/scale") core" \
  "CPU time (user+sys) of lasonic-replay / 20 s of log, 3 runs; includes writing the 1000x1000 AGM_OPERATIONAL maps"

model=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)
{
  echo "Machine: $(nproc) cores, ${model:-unknown CPU}; $(date -u +%Y-%m-%d), commit $(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo
  echo "| measure | value | how |"
  echo "|---|---|---|"
  printf '%s\n' "${rows[@]}"
} | tee "$out_dir/bench-$(date -u +%Y%m%dT%H%M%SZ).md"
