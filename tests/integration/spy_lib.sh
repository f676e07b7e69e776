# spy_lib.sh: what the two lcm-spy tests' inner parts share (lcm_spy_check.sh, spy_plugins_live.sh).
# Sourced inside the private namespace, under xvfb-run.

# play_into_spy PID OUT URL LOG TMP NAME TIMEOUT_S: waits until the probe (process PID, a real
# lcm-spy) has written TMP/ready, plays LOG into it with lcm-logplayer, touches TMP/done and exits
# with the probe's status. A probe that dies or is not ready within TIMEOUT_S exits 3 or 4; every
# message goes to OUT.
play_into_spy() {
  local pid=$1 out=$2 url=$3 log=$4 tmp=$5 name=$6 timeout=$7 rc deadline
  deadline=$((SECONDS + timeout))
  until [[ -e $tmp/ready ]]; do
    if ! kill -0 "$pid" 2>/dev/null; then
      rc=0; wait "$pid" || rc=$?
      echo "lcm-spy exited during start-up (status $rc)" >>"$out"
      exit 3
    fi
    if ((SECONDS >= deadline)); then
      kill -TERM "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true
      echo "lcm-spy did not finish start-up within $timeout s" >>"$out"
      exit 4
    fi
    sleep 0.2
  done
  sleep 1   # the spy's subscription is up before the first message
  timeout -k 5 60 lcm-logplayer --lcm-url="$url" "$log" >>"$out" 2>&1 || echo "lcm-logplayer failed or still playing after 60 s" >>"$out"
  touch "$tmp/done"
  rc=0; wait "$pid" || rc=$?
  ((rc == 0)) || echo "$name exited with status $rc" >>"$out"
  exit "$rc"
}
