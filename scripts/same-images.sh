#!/bin/bash
# Renders every fixture with every GPU technique by two builds of the command and reports the
# largest |V difference| of each image: the check that a refactor leaves the images unchanged.
#
#   scripts/same-images.sh OLD_PENUMBRA NEW_PENUMBRA [TECHNIQUE ...]
#
# Prints one line per image whose pixels differ and a total; exits non-zero if any differs.
set -euo pipefail
old=$1 new=$2
shift 2
techniques=("$@")
[ ${#techniques[@]} -gt 0 ] || techniques=(hard wedges wedges-blend pcf pcss fractional-disk mdsm gaussian)
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export NODEVICE_SELECT=1
same=0 differ=0
for scene in "$root"/fixtures/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  for t in "${techniques[@]}"; do
    rm -f "$work/old.exr" "$work/new.exr"
    for side in old new; do
      bin=$old; [ $side = new ] && bin=$new
      "$bin" render "$scene" --technique "$t" --backend gpu --out "$work/$side.exr" >/dev/null 2>&1 || true
    done
    if [ ! -e "$work/old.exr" ] || [ ! -e "$work/new.exr" ]; then
      differ=$((differ + 1))
      echo "$name $t: not rendered by $([ -e "$work/old.exr" ] && echo the new || echo the old) build"
      continue
    fi
    # An image of several lights compares channel by channel: the largest over them.
    max=$("$new" compare "$work/new.exr" "$work/old.exr" --json |
      python3 -c 'import json, sys; r = json.load(sys.stdin); print(max(c["all"]["max"] for c in (r if isinstance(r, list) else [r])))')
    if [ "$max" = "0.0" ]; then
      same=$((same + 1))
    else
      differ=$((differ + 1))
      echo "$name $t: max |dV| = $max"
    fi
  done
done
echo "$same images identical, $differ differ"
[ "$differ" -eq 0 ]
