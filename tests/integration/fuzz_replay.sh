#!/usr/bin/env bash
# fuzz_replay.sh [COUNT [SEED]]: the fuzz of fuzz.sh for the pipeline's channels (default 100000
# messages), written to a log and run through lasonic-replay (the complement and pilot stages,
# no network): deterministic, so a fault it finds is reproduced by the same seed. Every output
# must be valid (lasonic-fuzz check), and two replays must be bit-identical.
# Env: LASONIC_BIN, LASONIC_SOURCE.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
count=${1:-100000}
seed=${2:-2}
"$bin/lasonic-fuzz" write "$tmp/fuzz.lcmlog" "$count" "$seed" || die "lasonic-fuzz write failed"
for i in 1 2; do
  "$bin/lasonic-replay" --in "$tmp/fuzz.lcmlog" --out "$tmp/out$i.lcmlog" --config "$config" 2>"$tmp/replay$i.err" ||
    die "lasonic-replay failed on the fuzz log"
done
cmp -s "$tmp/out1.lcmlog" "$tmp/out2.lcmlog" || die "two replays of the same fuzz log differ"
"$bin/lasonic-fuzz" check "$tmp/out1.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
  cat "$tmp/check.out"
  die "outputs of the fuzz log: $(head -5 "$tmp/check.err")"
}
cat "$tmp/check.out"
grep -h "input errors" "$tmp/replay1.err" || true
echo "$test_name: PASS ($count messages, seed $seed)"
