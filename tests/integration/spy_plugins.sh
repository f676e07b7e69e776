#!/usr/bin/env bash
# spy_plugins.sh BUILD_DIR [OUTDIR]
#
# lasonic's lcm-spy plugins (lcmtypes/spy/, compiled into BUILD_DIR/lcmtypes.jar), headless:
# tests/integration/SpyPluginsCheck.java finds them as lcm-spy does, opens one message of each
# type (SECTOR_MAP, AGM_OPERATIONAL, CURRENT_SENSOR_MAP) through the plugin's action and checks
# the painted pixels, and feeds them bad messages. No display, no network.
# With OUTDIR the painted panels are kept there as PNG.
# Exit status: 0 pass, 1 fail, 77 skip (java, javac, lcm.jar or jchart2d.jar missing).
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $(basename "$0") BUILD_DIR [OUTDIR]" >&2
  exit 2
fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(cd "$1" && pwd)
jar=$build/lcmtypes.jar
skip() { echo "spy_plugins: SKIP: $*"; exit 77; }
fail() { echo "spy_plugins: FAIL: $*"; exit 1; }

command -v java >/dev/null 2>&1 || skip "java not found (default-jdk-headless)"
command -v javac >/dev/null 2>&1 || skip "javac not found (default-jdk-headless)"
find_jar() {  # name -> path of a system jar, or nothing
  local d
  for d in /usr/share/java /usr/local/share/java; do
    [[ -f $d/$1 ]] && { echo "$d/$1"; return 0; }
  done
  return 1
}
lcm_jar=$(find_jar lcm.jar) || skip "lcm.jar not found (liblcm-java)"
jchart_jar=$(find_jar jchart2d.jar) || skip "jchart2d.jar not found (libjchart2d-java)"
[[ -f $jar ]] || fail "$jar does not exist (javac and lcm.jar are present, so the build should have made it)"

tmp=$(mktemp -d -t spy-plugins.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
javac -nowarn -d "$tmp" -cp "$lcm_jar:$jar" "$here/SpyPluginsCheck.java" || fail "cannot compile SpyPluginsCheck.java"
# The class path of lcm-spy (README) plus the checker: lcm-spy's scan sees what a user's sees.
java -Djava.awt.headless=true -cp "$lcm_jar:$jchart_jar:$jar:$tmp" SpyPluginsCheck ${2:+"$2"} || fail "see above"
