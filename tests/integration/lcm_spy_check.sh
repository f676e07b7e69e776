#!/usr/bin/env bash
# lcm_spy_check.sh BUILD_DIR
#
# Checks that lcm-spy decodes every lasonic channel:
#  (a) BUILD_DIR/lcmtypes.jar holds a class <package>/<struct>.class for every
#      struct of every lcmtypes/*.lcm file;
#  (b) lcm-spy's own type database (lcm.spy.LCMTypeDatabase, the class-path scan
#      lcm-spy uses to name and decode a channel) finds every one of those
#      classes by its fingerprint;
#  (c) a short log of lasonic-sim (fig4_room, 3 s; run through lasonic-replay
#      when it is built, which adds the complement's and the pilot's channels)
#      is played with lcm-logplayer into the real lcm-spy (tests/integration/
#      SpyProbe.java runs lcm.spy.Spy in its JVM) under a virtual X server
#      (xvfb-run) inside a private network namespace. lcm-spy's channel table
#      must then list every channel of the log with our type name (not
#      "?? <fingerprint>", which is what lcm-spy shows for a type it does not
#      know), at least 90 % of the log's messages, 0 undecodable, and lcm-spy
#      must print no Java exception.
#
# Exit status: 0 pass, 1 fail, 77 skip (java, javac, xvfb-run, xauth, lcm.jar,
# jchart2d.jar or lcm-logplayer missing, or no private network namespace).
# Env: LCM_SPY_STARTUP_TIMEOUT (default 60) seconds allowed for start-up;
#      LCM_SPY_PNG=FILE also saves a screenshot of the spy window to FILE;
#      LCM_SPY_LOG=LOG plays LOG instead of the 3 s lasonic-sim log.
set -euo pipefail

LCM_URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'

# ---- inner part: runs inside the namespace, under xvfb-run ------------------
# --inner OUT CP URL JAR LOG TSV PNG: SpyProbe (the real lcm-spy) + lcm-logplayer LOG.
if [[ ${1:-} == --inner ]]; then
  out=$2 cp=$3 url=$4 jar=$5 log=$6 tsv=$7 png=$8
  tmp=$(dirname "$tsv")
  java -Djava.net.preferIPv4Stack=true -cp "$cp" SpyProbe "$url" "$jar" "$tmp/ready" "$tmp/done" \
    "$tsv" ${png:+"$png"} >"$out" 2>&1 &
  pid=$!
  # shellcheck source=spy_lib.sh
  source "$(dirname "${BASH_SOURCE[0]}")/spy_lib.sh"
  play_into_spy "$pid" "$out" "$url" "$log" "$tmp" SpyProbe ${LCM_SPY_STARTUP_TIMEOUT:-60}
fi

# ---- outer part ---------------------------------------------------------------
if [[ $# -ne 1 ]]; then
  echo "usage: $(basename "$0") BUILD_DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "$1" && pwd)
typesdir=$root/lcmtypes
jar=$build/lcmtypes.jar

skip() { echo "lcm_spy_check: SKIP: $*"; exit 77; }
fail() { echo "lcm_spy_check: FAIL: $*"; exit 1; }

find_jar() {  # name -> path of a system jar, or nothing
  local d
  for d in /usr/share/java /usr/local/share/java; do
    [[ -f $d/$1 ]] && { echo "$d/$1"; return 0; }
  done
  return 1
}

command -v java >/dev/null 2>&1 || skip "java not found (default-jdk-headless)"
command -v xvfb-run >/dev/null 2>&1 || skip "xvfb-run not found (xvfb)"
command -v xauth >/dev/null 2>&1 || skip "xauth not found (xauth; xvfb-run needs it)"
lcm_jar=$(find_jar lcm.jar) || skip "lcm.jar not found (liblcm-java)"
jchart_jar=$(find_jar jchart2d.jar) || skip "jchart2d.jar not found (libjchart2d-java)"
if [[ ! -f $jar ]]; then
  command -v javac >/dev/null 2>&1 || skip "javac not found, so $jar was not built"
  fail "$jar does not exist (javac and lcm.jar are present, so the build should have made it)"
fi

# ---- (a) one class per struct -------------------------------------------------
list_jar() {
  if command -v jar >/dev/null 2>&1; then jar tf "$1"
  elif command -v unzip >/dev/null 2>&1; then unzip -Z1 "$1"
  else python3 -c 'import sys, zipfile; print("\n".join(zipfile.ZipFile(sys.argv[1]).namelist()))' "$1"
  fi
}
entries=$(list_jar "$jar") || fail "cannot list $jar"

shopt -s nullglob
lcm_files=("$typesdir"/*.lcm)
((${#lcm_files[@]} > 0)) || fail "no .lcm files in $typesdir"
expected=()
for f in "${lcm_files[@]}"; do
  pkg=$(sed -n 's/^[[:space:]]*package[[:space:]]\+\([A-Za-z0-9_.]*\)[[:space:]]*;.*/\1/p' "$f" | head -n1)
  pkg=${pkg:-lasonic}
  structs=$(sed -n 's/^[[:space:]]*struct[[:space:]]\+\([A-Za-z0-9_]*\).*/\1/p' "$f")
  [[ -n $structs ]] || structs=$(basename "$f" .lcm)
  for s in $structs; do
    expected+=("${pkg//.//}/$s.class")
  done
done
missing=()
for c in "${expected[@]}"; do
  grep -qxF "$c" <<<"$entries" || missing+=("$c")
done
((${#missing[@]} == 0)) || fail "$jar lacks: ${missing[*]}"
echo "lcm_spy_check: (a) ok: $jar holds all ${#expected[@]} type classes of ${#lcm_files[@]} .lcm files"

# ---- (b), (c) lcm-spy knows every type and decodes a real log ---------------
command -v javac >/dev/null 2>&1 || skip "javac not found (default-jdk-headless)"
command -v lcm-logplayer >/dev/null 2>&1 || skip "lcm-logplayer not found (liblcm-bin)"
tmp=$(mktemp -d -t lcm-spy-check.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cp="$lcm_jar:$jchart_jar:$jar"
javac -d "$tmp" -cp "$cp" "$here/SpyProbe.java" || fail "cannot compile SpyProbe.java"

log=${LCM_SPY_LOG:-}
if [[ -z $log ]]; then
  bin=$build/bin
  [[ -x $bin/lasonic-sim ]] || fail "$bin/lasonic-sim was not built"
  "$bin/lasonic-sim" --scenario "$root/deploy/scenarios/fig4_room.yaml" --duration 3 \
    --out "$tmp/sim.lcmlog" >/dev/null || fail "lasonic-sim failed"
  log=$tmp/sim.lcmlog
  if [[ -x $bin/lasonic-replay ]]; then
    "$bin/lasonic-replay" --in "$tmp/sim.lcmlog" --out "$tmp/replay.lcmlog" \
      --config "$root/deploy/config/lasonic.yaml" >/dev/null 2>&1 || fail "lasonic-replay failed"
    log=$tmp/replay.lcmlog
  fi
fi
[[ -x $build/bin/lasonic-log-stats ]] || fail "$build/bin/lasonic-log-stats was not built"
# Channels and counts of the log: the "<CHANNEL> <count>" lines of lasonic-log-stats.
declare -A want=()
while read -r k v; do
  # LCM_SELF_TEST: raw bytes every LCM instance sends itself, no type (lcm-spy shows "??").
  [[ $k =~ ^[A-Z][A-Z0-9_]*$ && $k != LCM_SELF_TEST ]] && want[$k]=$v
done < <("$build/bin/lasonic-log-stats" "$log")
((${#want[@]} > 0)) || fail "no channels in $log"

out=$tmp/spy.txt
rc=0
"$root/tests/netns/in-netns.sh" xvfb-run -a -s '-screen 0 1024x600x24' "$0" --inner "$out" \
  "$cp:$tmp" "$LCM_URL" "$jar" "$log" "$tmp/table.tsv" "${LCM_SPY_PNG:-}" || rc=$?
echo "---- lcm-spy output ----"
cat "$out"
echo "---- lcm-spy channel table ----"
cat "$tmp/table.tsv" 2>/dev/null || true
echo "------------------------"
((rc != 77)) || skip "no private network namespace (see message above)"
((rc == 0)) || fail "lcm-spy did not run cleanly (status $rc)"
if grep -qE 'Exception|^Error|Could not create the Java Virtual Machine|Spy.messageReceived ex' "$out"; then
  fail "lcm-spy printed an error"
fi
if grep -q ' MISSING$' "$out"; then
  fail "lcm-spy's type database lacks: $(grep ' MISSING$' "$out" | awk '{print $2}' | tr '\n' ' ')"
fi
ntypes=$(grep -c '^type .* ok$' "$out" || true)
((ntypes >= ${#expected[@]})) ||
  fail "lcm-spy's type database found $ntypes of our types, expected ${#expected[@]}"
echo "lcm_spy_check: (b) ok: lcm-spy's type database finds all $ntypes types by fingerprint"

declare -A seen=()
bad=()
while IFS=$'\t' read -r ch type num _hz _per _jit _bw undec; do
  [[ $ch == Channel || $ch == LCM_SELF_TEST ]] && continue
  seen[$ch]=1
  [[ -n ${want[$ch]:-} ]] || { bad+=("$ch: not in the log"); continue; }
  [[ $type =~ ^[a-z0-9_]+_t$ ]] || bad+=("$ch: type '$type' not decoded")
  [[ $undec == 0 ]] || bad+=("$ch: $undec undecodable")
  ((num * 10 >= ${want[$ch]} * 9)) || bad+=("$ch: $num of ${want[$ch]} messages")
done <"$tmp/table.tsv"
for ch in "${!want[@]}"; do
  [[ -n ${seen[$ch]:-} ]] || bad+=("$ch: not listed by lcm-spy")
done
((${#bad[@]} == 0)) || fail "lcm-spy's channel table: ${bad[*]}"
echo "lcm_spy_check: (c) ok: lcm-spy decoded all ${#want[@]} channels of the log: $(printf '%s ' "${!want[@]}" | tr ' ' '\n' | sort | tr '\n' ' ')"
echo "lcm_spy_check: PASS"
