#!/usr/bin/env bash
# spy_plugins_live.sh BUILD_DIR
#
# lasonic's lcm-spy plugins in the real lcm-spy, as a user meets them: a lasonic-sim -> lasonic-
# replay log of fig7_lab (4 s) is played with lcm-logplayer into lcm-spy (lcm.spy.Spy, driven by
# tests/integration/SpyPluginProbe.java) under a virtual X server inside a private network
# namespace; the probe double-clicks SECTOR_MAP, AGM_OPERATIONAL and RADAR_MAP (and AGM_TACTICAL,
# CURRENT_SENSOR_MAP when the log has them) in lcm-spy's channel table, and each must open a
# lasonic map viewer that follows the stream (>= 2 messages) without an error.
#
# Exit status: 0 pass, 1 fail, 77 skip (java, javac, xvfb-run, xauth, lcm.jar, jchart2d.jar or
# lcm-logplayer missing, or no private network namespace).
# Env: SPY_PLUGINS_LOG=LOG plays LOG instead of the 4 s log; SPY_PLUGINS_DELAY_MS (default 0)
#      how long the viewers follow the stream at least before the check (and the screenshot); SPY_PLUGINS_PNG=FILE also saves a
#      screenshot of the screen (lcm-spy and the viewers) to FILE; SPY_PLUGINS_CHANNELS=A,B,C
#      the channels to open (default: as above).
set -euo pipefail

LCM_URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'

# ---- inner part: runs inside the namespace, under xvfb-run ------------------
# --inner OUT CP URL LOG CHANNELS DELAY PNG
if [[ ${1:-} == --inner ]]; then
  out=$2 cp=$3 url=$4 log=$5 channels=$6 delay=$7 png=$8
  tmp=$(dirname "$out")
  java -Djava.net.preferIPv4Stack=true -cp "$cp" SpyPluginProbe "$url" "$tmp/ready" "$tmp/done" \
    "$channels" "$delay" ${png:+"$png"} >"$out" 2>&1 &
  pid=$!
  # shellcheck source=spy_lib.sh
  source "$(dirname "${BASH_SOURCE[0]}")/spy_lib.sh"
  play_into_spy "$pid" "$out" "$url" "$log" "$tmp" SpyPluginProbe 60
fi

# ---- outer part ---------------------------------------------------------------
if [[ $# -ne 1 ]]; then
  echo "usage: $(basename "$0") BUILD_DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "$1" && pwd)
jar=$build/lcmtypes.jar

skip() { echo "spy_plugins_live: SKIP: $*"; exit 77; }
fail() { echo "spy_plugins_live: FAIL: $*"; exit 1; }
find_jar() {
  local d
  for d in /usr/share/java /usr/local/share/java; do
    [[ -f $d/$1 ]] && { echo "$d/$1"; return 0; }
  done
  return 1
}
command -v java >/dev/null 2>&1 || skip "java not found (default-jdk-headless)"
command -v javac >/dev/null 2>&1 || skip "javac not found (default-jdk-headless)"
command -v xvfb-run >/dev/null 2>&1 || skip "xvfb-run not found (xvfb)"
command -v xauth >/dev/null 2>&1 || skip "xauth not found (xauth; xvfb-run needs it)"
command -v lcm-logplayer >/dev/null 2>&1 || skip "lcm-logplayer not found (liblcm-bin)"
lcm_jar=$(find_jar lcm.jar) || skip "lcm.jar not found (liblcm-java)"
jchart_jar=$(find_jar jchart2d.jar) || skip "jchart2d.jar not found (libjchart2d-java)"
[[ -f $jar ]] || fail "$jar does not exist (javac and lcm.jar are present, so the build should have made it)"

tmp=$(mktemp -d -t spy-plugins-live.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cp="$lcm_jar:$jchart_jar:$jar"
javac -nowarn -d "$tmp" -cp "$cp" "$here/SpyPluginProbe.java" || fail "cannot compile SpyPluginProbe.java"

log=${SPY_PLUGINS_LOG:-}
if [[ -z $log ]]; then
  bin=$build/bin
  [[ -x $bin/lasonic-sim && -x $bin/lasonic-replay ]] || fail "lasonic-sim / lasonic-replay were not built"
  "$bin/lasonic-sim" --scenario "$root/deploy/scenarios/fig7_lab.yaml" --duration 4 \
    --out "$tmp/sim.lcmlog" >/dev/null || fail "lasonic-sim failed"
  "$bin/lasonic-replay" --in "$tmp/sim.lcmlog" --out "$tmp/replay.lcmlog" \
    --config "$root/deploy/config/lasonic.yaml" >/dev/null 2>&1 || fail "lasonic-replay failed"
  log=$tmp/replay.lcmlog
fi
channels=${SPY_PLUGINS_CHANNELS:-}
if [[ -z $channels ]]; then
  [[ -x $build/bin/lasonic-log-stats ]] || fail "$build/bin/lasonic-log-stats was not built"
  present=$("$build/bin/lasonic-log-stats" "$log" | awk '{print $1}')
  for ch in SECTOR_MAP AGM_OPERATIONAL AGM_TACTICAL CURRENT_SENSOR_MAP RADAR_MAP; do
    grep -qx "$ch" <<<"$present" && channels+=${channels:+,}$ch
  done
  # Four windows fit the screen beside lcm-spy's; RADAR_MAP is the line map of last resort.
  IFS=, read -r -a list <<<"$channels"
  if ((${#list[@]} > 3)); then channels=$(IFS=,; echo "${list[*]:0:3}"); fi
fi
[[ -n $channels ]] || fail "the log has none of SECTOR_MAP AGM_OPERATIONAL AGM_TACTICAL CURRENT_SENSOR_MAP RADAR_MAP"

out=$tmp/probe.txt
rc=0
"$root/tests/netns/in-netns.sh" xvfb-run -a -s '-screen 0 1280x800x24' "$0" --inner "$out" \
  "$cp:$tmp" "$LCM_URL" "$log" "$channels" "${SPY_PLUGINS_DELAY_MS:-0}" "${SPY_PLUGINS_PNG:-}" || rc=$?
echo "---- lcm-spy + probe output ----"
cat "$out"
echo "--------------------------------"
((rc != 77)) || skip "no private network namespace (see message above)"
if grep -qE 'Exception|^Error|Could not create the Java Virtual Machine' "$out"; then
  fail "lcm-spy or a plugin printed an error"
fi
((rc == 0)) || fail "the probe failed (status $rc)"
n=$(grep -c '^plugin .* ok ' "$out" || true)
IFS=, read -r -a list <<<"$channels"
((n == ${#list[@]})) || fail "$n of ${#list[@]} channels opened a live lasonic viewer"
echo "spy_plugins_live: PASS ($channels)"
