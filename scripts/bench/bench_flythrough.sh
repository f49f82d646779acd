#!/usr/bin/env bash
# Usage: scripts/bench/bench_flythrough.sh [rounds] [output-folder]
# Times the product's main job: a fly-through of the colon phantom on the 5-wall Immersive
# Cabin (10 images of 1400x1050 / 1050x1050 per stereo frame, PNGs and review sheets included)
# through the conformal map, with the defaults. Each round runs a 1-frame and an 11-frame
# fly-through and VTK's 1024^2 inside view of the yardstick (../shared/bench/vtk), alternated,
# so the ratio survives a noisy machine. Reports medians of
#   - the marginal wall time per stereo frame, (T(11 frames) - T(1 frame)) / 10: what a frame
#     costs once the volume, the map and the pipelines are loaded;
#   - the ray-casting device time per stereo frame in the same runs, and the host's share
#     (marginal / device: 1.0 means the host adds nothing);
#   - VTK's time for its view, and the marginal frame time as a multiple of it: the median over
#     rounds of each round's ratio, and that ratio at VTK's 0.37-0.38 s, the time the
#     yardstick's README (and the march-loop issue's 1.0 s target) measured on a quiet machine.
# Needs python3-vtk9, python3-numpy and xvfb for VTK (--no-vtk as third argument leaves it out).
# Default: 3 rounds.
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-3}
out=${2:-out/bench_flythrough}
with_vtk=${3:-}
cvc=build/app/cvc
mkdir -p "$out"
source scripts/bench/bench_scenes.sh
colon_phantom "$out" "$cvc"
[ "$with_vtk" = --no-vtk ] || yardstick_phantom "$out"
echo "device: $("$cvc" render "$out/colon.nrrd" --size 8x8 --force -o "$out/probe.png" | sed -n 's/^rendered 8x8 on \(.*\): ray.*/\1/p')"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"

# Prints "<wall seconds> <device ms per frame>" of one fly-through of $1 frames.
flythrough() {
  local line
  line=$("$cvc" render "$out/colon.nrrd" --display ic5 --path "$out/colon.json" --frames "$1" --force \
           -o "$out/frames_$1" 2>/dev/null | grep '^rendered')
  echo "$(echo "$line" | sed -n 's/.* in \([0-9.]*\) s,.*/\1/p') $(echo "$line" | sed -n 's/.*ray casting \([0-9.]*\) ms.*/\1/p')"
}
# VTK's seconds for its view; a black VTK image stops the script (through `v=$(vtk)`).
vtk() {
  local ms
  ms=$(vtk_yardstick_ms "$(cd "$out" && pwd)") || exit 1
  awk -v ms="$ms" 'BEGIN {printf "%.3f", ms / 1000}'
}

marginals=() devices=() vtks=() ratios=()
for ((r = 0; r < rounds; ++r)); do
  read -r t1 d1 < <(flythrough 1)
  read -r t11 d11 < <(flythrough 11)
  marginal=$(awk -v a="$t11" -v b="$t1" 'BEGIN {printf "%.3f", (a - b) / 10}')
  marginals+=("$marginal")
  devices+=("$(awk -v d="$d11" 'BEGIN {printf "%.3f", d / 1000}')")
  line="round $((r + 1)): 1 frame $t1 s, 11 frames $t11 s, marginal $marginal s/frame, device $(awk -v d="$d11" 'BEGIN {printf "%.3f", d / 1000}') s/frame"
  if [ "$with_vtk" != --no-vtk ]; then
    v=$(vtk)
    vtks+=("$v")
    ratios+=("$(awk -v m="$marginal" -v v="$v" 'BEGIN {printf "%.3f", m / v}')")
    line+=", VTK inside view $v s, ratio ${ratios[-1]}"
  fi
  echo "$line"
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
m=$(median "${marginals[@]}")
d=$(median "${devices[@]}")
echo "median: marginal wall time $m s per stereo frame, ray casting $d s per frame, host share (marginal / device) $(awk -v m="$m" -v d="$d" 'BEGIN {printf "%.2f", m / d}')"
if ((${#vtks[@]})); then
  v=$(median "${vtks[@]}")
  q=$(median "${ratios[@]}")
  echo "median: VTK inside view $v s; stereo frame = $(awk -v m="$m" -v v="$v" 'BEGIN {printf "%.2f", m / v}') x VTK's view"
  echo "median of the per-round ratios: $q x VTK's view; at VTK's 0.375 s on a quiet machine: $(awk -v q="$q" 'BEGIN {printf "%.2f", q * 0.375}') s per stereo frame"
fi
