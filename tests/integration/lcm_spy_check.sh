#!/usr/bin/env bash
# lcm_spy_check.sh BUILD_DIR
#
# Checks that lcm-spy can decode every lasonic channel:
#  (a) BUILD_DIR/lcmtypes.jar holds a class <package>/<struct>.class for every
#      struct of every lcmtypes/*.lcm file;
#  (b) lcm-spy (lcm.spy.Spy from lcm.jar, with jchart2d.jar and our jar on the
#      class path) starts under a virtual X server (xvfb-run) inside a private
#      network namespace, reports at least that many LCM types on the class path
#      ("Found N LCM types" -- lcm 1.3.1 prints only this count, not the names),
#      finishes its start-up ("Found N plugins"), stays up for a few seconds and
#      prints no Java exception.
#
# Exit status: 0 pass, 1 fail, 77 skip (java, javac, xvfb-run, xauth, lcm.jar or
# jchart2d.jar missing, or no private network namespace possible).
# Env: LCM_SPY_SECONDS (default 5) seconds to stay up after start-up;
#      LCM_SPY_STARTUP_TIMEOUT (default 60) seconds allowed for start-up.
set -euo pipefail

LCM_URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304'

# ---- inner part: runs inside the namespace, under xvfb-run ------------------
if [[ ${1:-} == --inner ]]; then
  out=$2 cp=$3 url=$4
  java -Djava.net.preferIPv4Stack=true -cp "$cp" lcm.spy.Spy --lcm-url="$url" >"$out" 2>&1 &
  pid=$!
  deadline=$((SECONDS + ${LCM_SPY_STARTUP_TIMEOUT:-60}))
  until grep -q '^Found [0-9]* plugins' "$out"; do
    if ! kill -0 "$pid" 2>/dev/null; then
      rc=0; wait "$pid" || rc=$?
      echo "lcm-spy exited during start-up (status $rc)" >>"$out"
      exit 3
    fi
    if ((SECONDS >= deadline)); then
      kill -TERM "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true
      echo "lcm-spy did not finish start-up within ${LCM_SPY_STARTUP_TIMEOUT:-60} s" >>"$out"
      exit 4
    fi
    sleep 0.2
  done
  sleep "${LCM_SPY_SECONDS:-5}"
  if ! kill -0 "$pid" 2>/dev/null; then
    rc=0; wait "$pid" || rc=$?
    echo "lcm-spy exited on its own (status $rc)" >>"$out"
    exit 3
  fi
  kill -TERM "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  exit 0
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

# ---- (b) lcm-spy starts and finds the types ----------------------------------
out=$(mktemp -t lcm-spy-check.XXXXXX)
trap 'rm -f "$out"' EXIT
rc=0
"$root/tests/netns/in-netns.sh" xvfb-run -a "$0" --inner "$out" \
  "$lcm_jar:$jchart_jar:$jar" "$LCM_URL" || rc=$?
echo "---- lcm-spy output ----"
cat "$out"
echo "------------------------"
((rc != 77)) || skip "no private network namespace (see message above)"
((rc == 0)) || fail "lcm-spy did not run cleanly (status $rc)"
if grep -qE 'Exception|^Error|Could not create the Java Virtual Machine' "$out"; then
  fail "lcm-spy printed an error"
fi
found=$(sed -n 's/^Found \([0-9]*\) LCM types.*/\1/p' "$out" | head -n1)
[[ -n $found ]] || fail "lcm-spy did not print 'Found N LCM types'"
((found >= ${#expected[@]})) ||
  fail "lcm-spy found $found LCM types on the class path, expected at least ${#expected[@]}"
echo "lcm_spy_check: (b) ok: lcm-spy found $found LCM types (expected >= ${#expected[@]}) and ran without errors"
echo "lcm_spy_check: PASS"
