#!/usr/bin/env bash
# Usage: scripts/bench/bench_first_light.sh [runs]
# Times `cvc render` at 1024x1024 on the default scenes (the ball phantom and the shipped
# abdominal CT): device time of the ray-casting dispatch and wall time of the whole command,
# median of N runs (default 5), run alternately so both scenes see the same machine load.
set -euo pipefail
cd "$(dirname "$0")/../.."
runs=${1:-5}
cvc=build/app/cvc
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$cvc" phantom --kind ball --size 128 -o "$tmp/ball.nrrd" > /dev/null
ct=../shared/data/ct/ts_example_abdomen_3mm.nrrd

declare -A device wall
for ((i = 0; i < runs; i++)); do
  for scene in ball abdomen; do
    if [ "$scene" = ball ]; then args=("$tmp/ball.nrrd" --iso 0); else args=("$ct" --iso -500); fi
    start=$(date +%s.%N)
    line=$("$cvc" render "${args[@]}" --size 1024x1024 --force -o "$tmp/$scene.png" | head -1)
    end=$(date +%s.%N)
    device[$scene]+="$(sed -E 's/.*ray casting ([0-9.]+) ms.*/\1/' <<< "$line") "
    wall[$scene]+="$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.3f", b - a}') "
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
echo "device: $("$cvc" render "$tmp/ball.nrrd" --size 8x8 --force -o "$tmp/x.png" | head -1 | sed -E 's/.* on (.*): ray.*/\1/')"
printf '| scene | ray casting (device, median ms) | whole command (median s) |\n|---|---|---|\n'
for scene in ball abdomen; do
  printf '| %s | %s | %s |\n' "$scene" "$(median <<< "${device[$scene]}")" "$(median <<< "${wall[$scene]}")"
done
