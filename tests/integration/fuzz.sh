#!/usr/bin/env bash
# fuzz.sh [COUNT [SEED]]: bad input on every input channel of every live process (lasonic-fuzz;
# default 100000 messages). Run it inside a private network namespace (ctest does; ./run soak with
# 1000000). Env: LASONIC_BIN, LASONIC_SOURCE.
# lasonic-complement and lasonic-pilot listen on one URL, the two simulated drivers on another
# (their outputs would otherwise be inputs of the first two), lasonic-navigator on a third (the
# complement's outputs would otherwise be its inputs too). lasonic-fuzz feeds them, then checks
# every message was received and counted (see fuzz.cpp); lcm-logger records both URLs and
# `lasonic-fuzz check` requires every output to be valid; every process must still run and exit 0
# on SIGTERM. Finally a short valid stream through a fresh pair (bad_messages' own check is the
# model) is not needed here: the processes answer a valid stream after the fuzz, checked by the
# heartbeat's "received" and the outputs' validity.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
count=${1:-100000}
seed=${2:-1}
pipe_url='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'
sim_url='udpm://239.255.76.67:7668?ttl=0&recv_buf_size=4194304'
nav_url='udpm://239.255.76.67:7669?ttl=0&recv_buf_size=4194304'

lcm-logger --lcm-url="$pipe_url" "$tmp/pipe.lcmlog" >"$tmp/logger-pipe.txt" 2>&1 &
logger_pipe=$!
pids+=("$logger_pipe")
lcm-logger --lcm-url="$sim_url" "$tmp/sim.lcmlog" >"$tmp/logger-sim.txt" 2>&1 &
logger_sim=$!
pids+=("$logger_sim")
lcm-logger --lcm-url="$nav_url" "$tmp/nav.lcmlog" >"$tmp/logger-nav.txt" 2>&1 &
logger_nav=$!
pids+=("$logger_nav")
start complement "$bin/lasonic-complement" --config "$config" --lcm-url "$pipe_url"
complement=$!
start pilot "$bin/lasonic-pilot" --config "$config" --lcm-url "$pipe_url"
pilot=$!
start laser "$bin/lasonic-laser-driver" --config "$config" --scenario "$scenario" --lcm-url "$sim_url"
laser=$!
start sonar "$bin/lasonic-sonar-driver" --config "$config" --scenario "$scenario" --lcm-url "$sim_url"
sonar=$!
start navigator "$bin/lasonic-navigator" --config "$config" --lcm-url "$nav_url"
navigator=$!

rc=0
"$bin/lasonic-fuzz" feed "$pipe_url" "$sim_url" "$nav_url" "$count" "$seed" >"$tmp/feed.out" 2>"$tmp/feed.err" || rc=$?
cat "$tmp/feed.out"
((rc == 0)) || die "fuzz feed: $(cat "$tmp/feed.err")"
for name in complement pilot laser sonar navigator; do
  p=${!name}
  kill -0 "$p" 2>/dev/null || die "lasonic-$name died under fuzzing"
  expect_term_exit "$p" "lasonic-$name:"
done
sleep 0.3
kill -INT "$logger_pipe" "$logger_sim" "$logger_nav"
wait "$logger_pipe" "$logger_sim" "$logger_nav" || true
"$bin/lasonic-fuzz" check "$tmp/pipe.lcmlog" "$tmp/sim.lcmlog" "$tmp/nav.lcmlog" >"$tmp/check.out" 2>"$tmp/check.err" || {
  cat "$tmp/check.out"
  die "outputs under fuzzing: $(head -5 "$tmp/check.err")"
}
cat "$tmp/check.out"
echo "$test_name: PASS"
