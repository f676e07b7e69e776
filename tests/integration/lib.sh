# lib.sh: what the integration test scripts share. Sourced, after `set -euo pipefail`, by
#   source "$(dirname "$0")/lib.sh"
# Env: LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root); both required.
# Sets: test_name (the script's file name, for messages), bin, src, url (LCM over a TTL-0
# multicast group: a test needing a bigger receive buffer appends &recv_buf_size=...), scenario
# (fig7_lab), config (the shipped configuration), tmp (a fresh directory, removed on exit) and
# pids (background processes, killed on exit).

# shellcheck disable=SC2034  # bin, scenario, config: for the sourcing script
test_name=$(basename "$0")
bin=${LASONIC_BIN:?set LASONIC_BIN}
src=${LASONIC_SOURCE:?set LASONIC_SOURCE}
url='udpm://239.255.76.67:7667?ttl=0'
scenario=$src/deploy/scenarios/fig7_lab.yaml
config=$src/deploy/config/lasonic.yaml
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

# die MESSAGE...: prints "<test>: FAIL: MESSAGE" and the tails of the files under $tmp matching
# die_globs (a test may append more globs), exits 1.
die_globs=('*.err')
die() {
  echo "$test_name: FAIL: $*" >&2
  local g f
  for g in "${die_globs[@]}"; do
    # shellcheck disable=SC2086  # $g is a glob
    for f in "$tmp"/$g; do [[ -f $f ]] && { echo "--- $f" >&2; tail -20 "$f" >&2; }; done
  done
  exit 1
}

# stat KEY: the value of KEY in $tmp/stats ("key value" lines, lasonic-log-stats / -sonar-check).
stat() { awk -v k="$1" '$1 == k {print $2}' "$tmp/stats"; }

# start ERR CMD...: runs CMD in the background, stdout and stderr to $tmp/ERR.err, its pid added
# to pids; $! is its pid after the call.
start() {
  "${@:2}" 2>"$tmp/$1.err" >&2 &
  pids+=("$!")
}

# start_logger LOG [ERR]: lcm-logger on $url recording $tmp/LOG, output to $tmp/ERR (default
# logger.err); its pid in logger and pids. stop_logger: SIGINT, wait.
start_logger() {
  logger_err=${2:-logger.err}
  lcm-logger --lcm-url="$url" "$tmp/$1" >"$tmp/$logger_err" 2>&1 &
  logger=$!
  pids+=("$logger")
}
stop_logger() {
  kill -INT "$logger"
  local rc=0
  wait_exit "$logger" 10 || rc=$?
  ((rc != 124)) || die "lcm-logger still running 10 s after SIGINT"
}
# start_recorder NAME LOG: lasonic-fault-check record (a queue of 100 000, where lcm-logger's 30
# drop the rest of a burst on a loaded machine) on $url, every channel to $tmp/LOG, started as
# NAME (start, wait_ready NAME); its pid in recorder. stop_recorder: SIGINT, wait.
start_recorder() {
  start "$1" "$bin/lasonic-fault-check" record "$url" "$tmp/$2" '.*'
  recorder=$!
}
stop_recorder() {
  kill -INT "$recorder"
  local rc=0
  wait_exit "$recorder" 10 || rc=$?
  ((rc != 124)) || die "the recorder still running 10 s after SIGINT"
}

# play_log SECONDS LOG [ERR [ARGS...]]: lcm-logplayer plays LOG on $url in real time (ARGS
# before the log, e.g. -e REGEX), output to $tmp/ERR (default player.err); dies when it fails
# or is still playing SECONDS after its start (so a stuck player fails its test with a message
# naming it, not by ctest's timeout with none). SECONDS: the log's length plus a margin.
play_log() {
  local limit=$1 log=$2 err=${3:-player.err} rc=0
  shift $(($# < 3 ? $# : 3))
  timeout -k 5 "$limit" lcm-logplayer --lcm-url="$url" "$@" "$log" >"$tmp/$err" 2>&1 || rc=$?
  ((rc != 124)) || die "lcm-logplayer still playing $(basename "$log") $limit s after its start"
  ((rc == 0)) || die "lcm-logplayer failed (exit status $rc) on $(basename "$log")"
}

# wait_ready ERR...: waits until each process started as `start ERR ...` has logged that it is
# running (a lasonic process does once its subscriptions are up) and, if a logger was started,
# until lcm-logger has opened its log; at most 60 s in all, else dies naming the one that has
# not. Used instead of a fixed pause before the input is published: on a loaded machine a
# process may take longer than any pause to start, and its input would be lost unheard.
wait_ready() {
  local deadline=$((SECONDS + 60)) name file pattern
  local -a waits=("$@")
  [[ -n ${logger_err:-} ]] && waits+=("$logger_err:logger")
  for name in "${waits[@]}"; do
    if [[ $name == *:logger ]]; then
      file=$tmp/${name%:logger} pattern='^Opening log file'
    else
      file=$tmp/$name.err pattern=' running$'
    fi
    until grep -q "$pattern" "$file" 2>/dev/null; do
      ((SECONDS < deadline)) || die "${name%:logger} not running 60 s after its start"
      sleep 0.05
    done
  done
}

# wait_exit PID SECONDS: waits at most SECONDS for the child PID to exit and returns its exit
# status, or 124 if it is still running then (a hung process fails its test with a message
# instead of running into ctest's timeout with none).
wait_exit() {
  local i state
  for ((i = 0; i < $2 * 10; i++)); do
    state=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null || true)
    if [[ -z $state || $state == Z ]]; then
      wait "$1"
      return
    fi
    sleep 0.1
  done
  return 124
}

# expect_term_exit PID [WHO]: SIGTERM to PID, which must exit 0;
# else die "[WHO ]exit status RC after SIGTERM, expected 0".
expect_term_exit() {
  kill -TERM "$1"
  local rc=0
  wait_exit "$1" 20 || rc=$?
  ((rc != 124)) || die "${2:+$2 }still running 20 s after SIGTERM"
  [[ $rc -eq 0 ]] || die "${2:+$2 }exit status $rc after SIGTERM, expected 0"
}

# expect_config_error NAME KEY CMD...: CMD --lcm-url $url (stdout $tmp/NAME.out, stderr
# $tmp/NAME.err) exits 2 and its error names KEY (fixed string).
expect_config_error() {
  local name=$1 key=$2 rc=0
  shift 2
  "$@" --lcm-url "$url" >"$tmp/$name.out" 2>"$tmp/$name.err" || rc=$?
  [[ $rc -eq 2 ]] || die "$name: exit status $rc, expected 2"
  grep -qF "$key" "$tmp/$name.err" || die "$name: the error does not name $key"
}

# expect_bad_config PATTERN KEY CMD...: CMD --lcm-url $url (output to $tmp/bad.err) exits 2 and
# its error matches PATTERN (grep regex); else die "bad config: ..." naming KEY.
expect_bad_config() {
  local pattern=$1 key=$2 rc=0
  shift 2
  "$@" --lcm-url "$url" 2>"$tmp/bad.err" >&2 || rc=$?
  [[ $rc -eq 2 ]] || die "bad config: exit status $rc, expected 2"
  grep -q "$pattern" "$tmp/bad.err" || die "bad config: error does not name $key"
}

# config_with SECTION KEY VALUE OUT: the shipped configuration with SECTION.KEY set to VALUE (a
# top-level section, a key directly under it), written to OUT; e.g.
#   config_with pilot remembered true "$tmp/remembered.yaml"
config_with() {
  # Two passes over the file: replace the key where the section has it, else add it first.
  awk -v sec="$1" -v key="$2" -v val="$3" '
    FNR == 1 { in_sec = 0 }
    /^[A-Za-z_]+:/ { in_sec = ($0 ~ "^" sec ":") }
    FNR == NR { if (in_sec && $0 ~ "^  " key ":") has = 1; next }
    in_sec && $0 ~ "^  " key ":" { print "  " key ": " val; next }
    { print }
    $0 ~ "^" sec ":" && !has { print "  " key ": " val }
  ' "$config" "$config" >"$4"
  grep -q "^  $2: $3\$" "$4" || die "config_with: could not set $1.$2 in $4"
}
