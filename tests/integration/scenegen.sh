#!/usr/bin/env bash
# scenegen.sh: lasonic-scenegen, the random scenes of `./run score --random` (no network). Env:
# LASONIC_BIN (build/bin), LASONIC_SOURCE (repository root).
#  1. three scenes and scenes.list (suite.list's format, a Pioneer-type scene with its overlay);
#  2. the same indices again give byte-identical files;
#  3. a generated scene with the list's overlays runs through lasonic-sim -> lasonic-replay ->
#     lasonic-eval and is scored (the sector map's rates in [0, 1]);
#  4. an --out that cannot be made exits 2 naming it.
set -euo pipefail

source "$(dirname "$0")/lib.sh"
cd "$src"  # scenes.list names overlays from the repository's root, as suite.list does

"$bin/lasonic-scenegen" --first 3 --count 3 --out "$tmp/a" >"$tmp/gen.err" 2>&1 || die "lasonic-scenegen failed"
"$bin/lasonic-scenegen" --first 3 --count 3 --out "$tmp/b" >>"$tmp/gen.err" 2>&1 || die "lasonic-scenegen failed"
mapfile -t lines < <(grep -v '^#' "$tmp/a/scenes.list")
((${#lines[@]} == 3)) || die "scenes.list has ${#lines[@]} scenes, expected 3: $(cat "$tmp/a/scenes.list")"
for i in 3 4 5; do
  f=$(printf 'random_%03d.yaml' "$i")
  [[ -f $tmp/a/$f ]] || die "no $f"
  cmp -s "$tmp/a/$f" "$tmp/b/$f" || die "$f differs between two runs with the same indices"
  grep -q "^name: ${f%.yaml}$" "$tmp/a/$f" || die "$f: name is not ${f%.yaml}"
done
# Scene 4 is a Pioneer-type scene (its sensors are in the scene, its pipeline overlay in the list).
grep -qx "$tmp/a/random_004.yaml deploy/config/pioneer.yaml" "$tmp/a/scenes.list" ||
  die "random_004 is not listed with the Pioneer overlay: $(cat "$tmp/a/scenes.list")"
grep -q 'beam_deg: 25' "$tmp/a/random_004.yaml" || die "random_004 has no Pioneer sonar overrides"
echo "$test_name: (1, 2) ok: three scenes, listed with their overlays, deterministic"

# (3) The Pioneer scene scored as `./run score --random` scores it.
read -r yaml overlays <<<"${lines[1]}"
cfg=(--config "$config")
for o in $overlays; do cfg+=(--config "$o"); done
"$bin/lasonic-sim" --scenario "$yaml" --out "$tmp/raw.lcmlog" --duration 10 "${cfg[@]}" >"$tmp/sim.err" 2>&1 ||
  die "lasonic-sim failed on $yaml"
"$bin/lasonic-replay" --in "$tmp/raw.lcmlog" --out "$tmp/out.lcmlog" "${cfg[@]}" >"$tmp/replay.err" 2>&1 ||
  die "lasonic-replay failed"
"$bin/lasonic-eval" --log "$tmp/out.lcmlog" --scenario "$yaml" "${cfg[@]}" >"$tmp/table.txt" 2>"$tmp/eval.err" ||
  die "lasonic-eval failed"
for k in missed_rate false_alarm_rate; do
  v=$(awk -v k="sector_map.$k" '$1 == k {print $2}' "$tmp/table.txt")
  [[ -n $v ]] || die "no sector_map.$k"
  awk -v v="$v" 'BEGIN {exit !(v >= 0 && v <= 1)}' || die "sector_map.$k = $v not in [0, 1]"
  echo "  random_004, 10 s: sector_map.$k $v"
done
echo "$test_name: (3) ok: a generated scene runs through the offline pipeline and is scored"

# (4) An output directory that cannot be made.
rc=0
"$bin/lasonic-scenegen" --out /proc/lasonic-none >"$tmp/bad.err" 2>&1 || rc=$?
[[ $rc -eq 2 ]] || die "--out /proc/lasonic-none: exit $rc, expected 2"
grep -qF -- "--out /proc/lasonic-none" "$tmp/bad.err" || die "the error does not name --out: $(cat "$tmp/bad.err")"
echo "$test_name: (4) ok: $(head -n 1 "$tmp/bad.err")"
