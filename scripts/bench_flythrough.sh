#!/usr/bin/env bash
# Usage: scripts/bench_flythrough.sh [frames] [output-folder]
# Times the product's main job: a fly-through of the colon phantom on the 5-wall Immersive
# Cabin (10 images of 1400x1050 / 1050x1050 per stereo frame) through the conformal map: the
# defaults (1-voxel step, empty-space skipping), a half-voxel step, skipping off, and one frame
# at the demo's polyp pose. Runs alternate on the same frames. Prints seconds per
# stereo frame (whole command: ray casting, read-back, PNG encoding, sheets) and the device time
# of the ray casting alone, and frames per minute. Default: 10 frames.
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-10}
out=${2:-out/bench_flythrough}
cvc=build/app/cvc
mkdir -p "$out"
[ -f "$out/colon.nrrd" ] || "$cvc" phantom -o "$out/colon.nrrd" > /dev/null
echo "device: $(vulkaninfo --summary 2>/dev/null | grep -m1 deviceName | sed 's/.*= //')"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
run() {
  local label=$1; shift
  local line
  line=$("$cvc" render "$out/colon.nrrd" --display ic5 --force "$@" 2>/dev/null | grep '^rendered')
  echo "$label: $line"
}
run "fly-through, $frames frames, defaults (step 1 voxel, skipping)" --path "$out/colon.json" --frames "$frames" -o "$out/frames_default"
run "fly-through, $frames frames, step 0.5 voxel, skipping      " --path "$out/colon.json" --frames "$frames" --step 0.5 -o "$out/frames_half_step"
run "fly-through, $frames frames, step 1 voxel, no skipping     " --path "$out/colon.json" --frames "$frames" --no-skip -o "$out/frames_no_skip"
run "polyp 3 pose (the demo's), 1 frame, defaults" --path "$out/colon.json" --polyp 3 --polyp-elevation 50 --scale 4 -o "$out/polyp3"
