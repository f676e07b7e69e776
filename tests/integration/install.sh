#!/usr/bin/env bash
# install.sh BUILD_DIR: `cmake --install` into a temporary prefix gives what README "Installing"
# says: every process in PREFIX/bin answers --help and --version and no test helper is there; the
# installed deploy/ tree runs the offline pipeline (lasonic-sim -> lasonic-replay -> lasonic-eval)
# with output bit-identical to the build tree's, and its host profiles pass `lasonic-launch
# --check`; a separate CMake project finds the package (find_package(lasonic)), builds against the
# installed message types and channel names, and round-trips a sector_map_t. No network.
set -euo pipefail
build=$(cd "${1:?usage: install.sh BUILD_DIR}" && pwd)
src=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install.sh: FAIL: $*" >&2; exit 1; }
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" >"$tmp/install.out" 2>&1 || { cat "$tmp/install.out"; fail "cmake --install"; }

for p in lasonic-complement lasonic-pilot lasonic-navigator lasonic-sim lasonic-sim-world lasonic-laser-driver \
         lasonic-sonar-driver lasonic-replay lasonic-eval lasonic-eval-table lasonic-render lasonic-launch \
         lasonic-scenegen; do
  [[ -x $prefix/bin/$p ]] || fail "$p not installed in PREFIX/bin"
done
for p in "$prefix"/bin/*; do
  "$p" --help >/dev/null 2>&1 || fail "installed $(basename "$p") --help failed"
  "$p" --version 2>&1 | grep -Eq '^lasonic [0-9]+\.[0-9]+\.[0-9]+ \((git [0-9a-f]|unknown)' ||
    fail "installed $(basename "$p") --version: $("$p" --version 2>&1 | head -1)"
done
for p in lasonic-bad-messages lasonic-fuzz lasonic-log-stats lasonic-latency; do
  [[ ! -e $prefix/bin/$p ]] || fail "test helper $p installed"
done
for f in include/lasonic/sector_map_t.hpp include/lasonic/channels.hpp lib/cmake/lasonic/lasonicConfig.cmake \
         lib/cmake/lasonic/lasonicConfigVersion.cmake share/lasonic/deploy/config/lasonic.yaml \
         share/lasonic/deploy/hosts/pilot.yaml share/lasonic/deploy/systemd/lasonic@.service \
         share/lasonic/deploy/scenarios/fig4_room.yaml; do
  [[ -f $prefix/$f ]] || fail "PREFIX/$f not installed"
done
if [[ -f $build/lcmtypes.jar ]]; then
  cmp "$build/lcmtypes.jar" "$prefix/share/lasonic/lcmtypes.jar" || fail "lcmtypes.jar not installed as built"
fi

# The installed tree runs on its own: from PREFIX/share/lasonic, as the systemd units do.
cd "$prefix/share/lasonic"
# (The demo's profile takes what `run demo` sets with --set.)
demo_vars=(--set scenario=deploy/scenarios/fig7_lab.yaml --set duration=5 --set "lcmlog=$tmp/demo.lcmlog")
for h in deploy/hosts/*.yaml; do
  extra=()
  [[ $(basename "$h") == demo.yaml ]] && extra=("${demo_vars[@]}")
  "$prefix/bin/lasonic-launch" "$h" --check "${extra[@]}" >"$tmp/check.out" 2>&1 ||
    { cat "$tmp/check.out"; fail "lasonic-launch --check $h"; }
done
"$prefix/bin/lasonic-sim" --scenario deploy/scenarios/fig4_room.yaml --config deploy/config/lasonic.yaml --duration 4 \
  --out "$tmp/sim.lcmlog" >/dev/null 2>&1 || fail "installed lasonic-sim"
"$prefix/bin/lasonic-replay" --in "$tmp/sim.lcmlog" --out "$tmp/installed.lcmlog" --config deploy/config/lasonic.yaml \
  >/dev/null 2>&1 || fail "installed lasonic-replay"
"$build/bin/lasonic-replay" --in "$tmp/sim.lcmlog" --out "$tmp/built.lcmlog" --config "$src/deploy/config/lasonic.yaml" \
  >/dev/null 2>&1 || fail "build tree's lasonic-replay"
cmp "$tmp/installed.lcmlog" "$tmp/built.lcmlog" || fail "the installed tree's replay differs from the build tree's"
"$prefix/bin/lasonic-eval" --log "$tmp/installed.lcmlog" --scenario deploy/scenarios/fig4_room.yaml \
  --config deploy/config/lasonic.yaml --json "$tmp/eval.json" >/dev/null 2>&1 || fail "installed lasonic-eval"
grep -q '"maps": [1-9]' "$tmp/eval.json" || fail "installed lasonic-eval scored no sector maps"

# A program of one's own, built against the installed package only.
mkdir -p "$tmp/consumer"
cat >"$tmp/consumer/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(consumer CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(lasonic 0.1 REQUIRED)
add_executable(consumer main.cpp)
target_link_libraries(consumer PRIVATE lasonic::lcmtypes)
file(WRITE ${CMAKE_BINARY_DIR}/deploy_dir.txt "${LASONIC_DEPLOY_DIR}")
file(WRITE ${CMAKE_BINARY_DIR}/jar.txt "${LASONIC_LCMTYPES_JAR}")
CMAKE
cat >"$tmp/consumer/main.cpp" <<'CPP'
#include <lasonic/channels.hpp>
#include <lasonic/sector_map_t.hpp>

#include <cstdio>
#include <cstring>
#include <vector>

int main() {
  lasonic::sector_map_t m{};
  m.utime = 42;
  m.nsectors = 48;
  m.distance.assign(48, -1.0f);
  m.distance[7] = 1.25f;
  // (A copy: LCM 1.3.1's constants are declared, not defined, so they cannot bind to a reference.)
  const int8_t none = lasonic::sector_map_t::SOURCE_NONE;
  m.source.assign(48, none);
  m.source[7] = lasonic::sector_map_t::SOURCE_SONAR;
  m.laser_distance.assign(48, -1.0f);
  m.sonar_distance.assign(48, -1.0f);
  m.sonar_distance[7] = 1.25f;
  m.remembered_distance.assign(48, -1.0f);
  std::vector<unsigned char> buf(static_cast<size_t>(m.getEncodedSize()));
  if (m.encode(buf.data(), 0, static_cast<int>(buf.size())) < 0) return 1;
  lasonic::sector_map_t back{};
  if (back.decode(buf.data(), 0, static_cast<int>(buf.size())) < 0) return 2;
  if (back.utime != 42 || back.nsectors != 48 || back.distance[7] != 1.25f ||
      back.source[7] != lasonic::sector_map_t::SOURCE_SONAR)
    return 3;
  if (std::strcmp(lasonic::channels::SECTOR_MAP, "SECTOR_MAP") != 0) return 4;
  std::printf("%s round trip ok\n", lasonic::channels::SECTOR_MAP);
  return 0;
}
CPP
cmake -S "$tmp/consumer" -B "$tmp/consumer/build" -DCMAKE_PREFIX_PATH="$prefix" >"$tmp/consumer.out" 2>&1 ||
  { cat "$tmp/consumer.out"; fail "find_package(lasonic) in a separate project"; }
cmake --build "$tmp/consumer/build" >>"$tmp/consumer.out" 2>&1 || { cat "$tmp/consumer.out"; fail "building against the installed types"; }
"$tmp/consumer/build/consumer" || fail "the installed types' round trip (exit $?)"
[[ $(cat "$tmp/consumer/build/deploy_dir.txt") == "$prefix/share/lasonic/deploy" ]] || fail "LASONIC_DEPLOY_DIR is not PREFIX/share/lasonic/deploy"
# The jar variable names the installed jar, and only when one was built.
jar=$(cat "$tmp/consumer/build/jar.txt")
if [[ -f $build/lcmtypes.jar ]]; then
  [[ $jar == "$prefix/share/lasonic/lcmtypes.jar" ]] || fail "LASONIC_LCMTYPES_JAR is '$jar', not PREFIX/share/lasonic/lcmtypes.jar"
else
  [[ -z $jar ]] || fail "LASONIC_LCMTYPES_JAR is '$jar' though no jar was built"
fi
echo "install.sh: PASS"
