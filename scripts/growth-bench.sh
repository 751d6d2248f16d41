#!/bin/bash
# Measures how the cost of the reference, depth-complexity sampling and penumbra-wedges blending
# grows with the triangles and with the light's size, on the scenes scripts/growth-scenes.py
# writes, and prints a Markdown table.
#
#   scripts/growth-bench.sh OUT_DIR [ROUNDS] [SCENE ...]
#
# OUT_DIR  the folder written by `python3 scripts/growth-scenes.py OUT_DIR`, or any folder of
#          scenes (fixtures/scenes, fixtures/scale)
# ROUNDS   rounds, default 5; each round renders one scene with the three techniques in turn,
#          so that a slow spell of the machine weighs on all three alike
# SCENE    only these scenes: names or quoted globs, with or without .toml, one per argument or
#          several in one (e.g. 'tris-10k light-*'); default all, in the order tris-10k, tris-50k,
#          tris-200k, tris-1m, light-0.25x, light-1x, light-4x, light-low, wide-ground
#
# Every run is `penumbra render SCENE --technique T --backend cpu` (reference and
# depth-complexity with --samples 256), timed by /usr/bin/time: the CPU time of the whole process
# (user + system, all threads summed, loading and building included) and its peak resident
# memory. The table gives the median of each over the rounds, the ratios of the medians to the
# reference's, the scene's triangles (faces of its OBJ files, a mesh counted once per placement)
# and its silhouette edges from the light's centre (`penumbra geometry`, the edges that carry the
# wedges; one count per light, "44 + 52", for a scene of several). Progress goes to stderr, the table to stdout. Uses target/release/penumbra, copied at
# the start so that a rebuild during the run does not change what is measured.
set -euo pipefail

usage() {
  sed -n '6,15p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 1
}
[ $# -ge 1 ] || usage
dir=$1
rounds=${2:-5}
shift $(($# >= 2 ? 2 : 1))
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "growth-bench.sh: ROUNDS must be a positive integer, not '$rounds'" >&2; exit 1; }
[ -d "$dir" ] || { echo "growth-bench.sh: $dir is not a folder (write it with scripts/growth-scenes.py)" >&2; exit 1; }

root=$(cd "$(dirname "$0")/.." && pwd)
built=$root/target/release/penumbra
if [ ! -x "$built" ]; then
  echo "growth-bench.sh: $built is missing; build it first: cargo build --release" >&2
  exit 1
fi
if [ ! -x /usr/bin/time ]; then
  echo "growth-bench.sh: /usr/bin/time (GNU time) is missing; it measures CPU time and memory" >&2
  exit 1
fi

export NODEVICE_SELECT=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bin=$work/penumbra
cp "$built" "$bin"
out=/tmp/growth.exr

# The scenes to run, in table order, filtered by the SCENE patterns: those of
# scripts/growth-scenes.py in the order above, or else every scene of the folder by name (so that
# the same table can be made for fixtures/scenes or fixtures/scale).
order=(tris-10k tris-50k tris-200k tris-1m light-0.25x light-1x light-4x light-low wide-ground)
if ! ls "$dir/${order[0]}.toml" >/dev/null 2>&1; then
  order=()
  for f in "$dir"/*.toml; do
    [ -f "$f" ] && order+=("$(basename "$f" .toml)")
  done
fi
patterns=()
for arg in "$@"; do
  read -ra words <<<"${arg//,/ }"
  for p in "${words[@]}"; do
    patterns+=("$(basename "${p%.toml}")")
  done
done
scenes=()
for name in "${order[@]}"; do
  [ -f "$dir/$name.toml" ] || continue
  if [ ${#patterns[@]} -eq 0 ]; then
    scenes+=("$name")
    continue
  fi
  for p in "${patterns[@]}"; do
    # shellcheck disable=SC2053 # the pattern is a glob on purpose
    if [[ $name == $p ]]; then
      scenes+=("$name")
      break
    fi
  done
done
for p in "${patterns[@]}"; do
  hit=0
  for name in "${scenes[@]}"; do
    # shellcheck disable=SC2053
    [[ $name == $p ]] && hit=1
  done
  [ $hit -eq 1 ] || { echo "growth-bench.sh: no scene of $dir matches '$p' (scenes: ${order[*]})" >&2; exit 1; }
done
[ ${#scenes[@]} -gt 0 ] || { echo "growth-bench.sh: no scene in $dir (write them with scripts/growth-scenes.py)" >&2; exit 1; }

techniques=(reference depth-complexity wedges-blend)
declare -A flags=([reference]="--samples 256" [depth-complexity]="--samples 256" [wedges-blend]="")

median() {
  printf '%s\n' "$@" | sort -g |
    awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'
}

# Triangles of a scene: the faces of each OBJ its [[mesh]] entries name, polygons fanned.
declare -A obj_tris=()
triangles() {
  local scene=$1 total=0 obj
  while read -r obj; do
    if [ -z "${obj_tris[$obj]:-}" ]; then
      obj_tris[$obj]=$(awk '$1 == "f" {n += NF - 3} END {print n + 0}' "$(dirname "$scene")/$obj")
    fi
    total=$((total + obj_tris[$obj]))
  done < <(sed -n 's/^obj *= *"\(.*\)".*/\1/p' "$scene")
  echo "$total"
}

rows=()
for name in "${scenes[@]}"; do
  scene=$dir/$name.toml
  tris=$(triangles "$scene")
  # One count per light, joined with " + " for a scene of several.
  sil=$("$bin" geometry "$scene" | sed -n 's/.*: \([0-9]*\) silhouette edges.*/\1/p' | paste -sd '+' | sed 's/+/ + /g')
  declare -A cpu=() mem=()
  for t in "${techniques[@]}"; do cpu[$t]="" mem[$t]=""; done
  for r in $(seq "$rounds"); do
    for t in "${techniques[@]}"; do
      # shellcheck disable=SC2086 # flags[$t] is a list of words
      if ! /usr/bin/time -f "%U %S %M" -o "$work/time" "$bin" render "$scene" --technique "$t" \
        ${flags[$t]} --backend cpu --out "$out" >/dev/null 2>"$work/err"; then
        echo "growth-bench.sh: penumbra render $scene --technique $t failed:" >&2
        cat "$work/err" >&2
        exit 1
      fi
      read -r user sys kb < <(tail -n 1 "$work/time")
      s=$(awk -v u="$user" -v s="$sys" 'BEGIN {printf "%.2f", u + s}')
      cpu[$t]+="$s "
      mem[$t]+="$kb "
      echo "$name round $r/$rounds: $t ${s} s CPU, $(awk -v k="$kb" 'BEGIN {printf "%.0f", k / 1024}') MiB" >&2
    done
  done
  declare -A med=() peak=()
  for t in "${techniques[@]}"; do
    # shellcheck disable=SC2086 # one number per word
    med[$t]=$(median ${cpu[$t]})
    # shellcheck disable=SC2086
    peak[$t]=$(median ${mem[$t]})
  done
  rows+=("$(awk -v n="$name" -v tr="$tris" -v sil="${sil:-?}" -v r="${med[reference]}" \
    -v d="${med[depth-complexity]}" -v w="${med[wedges-blend]}" -v mr="${peak[reference]}" \
    -v md="${peak[depth-complexity]}" -v mw="${peak[wedges-blend]}" 'BEGIN {
      printf "| %s | %d | %s | %.2f | %.2f | %.2f | %s | %s | %.0f | %.0f | %.0f |\n", n, tr, sil,
        r, d, w, (r > 0 ? sprintf("%.3f", d / r) : "-"), (r > 0 ? sprintf("%.3f", w / r) : "-"),
        mr / 1024, md / 1024, mw / 1024 }')")
done

echo "Median over $rounds round(s) of the CPU time (user + system, all threads, $(nproc) cores) and peak"
echo "resident memory of each \`penumbra render --backend cpu\` process; reference and"
echo "depth-complexity at 256 light samples per pixel."
echo
echo "| scene | triangles | silhouette edges (light centre) | reference (s) | depth-complexity (s) | wedges-blend (s) | depth-complexity / reference | wedges-blend / reference | reference peak (MiB) | depth-complexity peak (MiB) | wedges-blend peak (MiB) |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
printf '%s\n' "${rows[@]}"
