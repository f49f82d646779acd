#!/usr/bin/env bash
# Usage: scripts/bench/bench_refinement.sh [output-folder]
# How many bisection steps an iso hit needs: renders three inside views (the VTK yardstick's
# phantom and camera, the colon phantom, the shared 3 mm abdominal CT; 1024^2, iso -500 HU,
# central-difference normals) at steps of 0.5 and 1 voxel with 0, 2 and 6 bisection steps
# (each followed by a linear interpolation in the last bracket; 0: the raw sample) and compares
# each with 12 steps on the same samples: the distance between the first hits (mm) and the
# pixels' largest channel difference. Then the same 12-step image against a 0.1-voxel tricubic
# render (B-spline normals, which the tricubic filter always uses), the sampling's own error,
# for scale. Needs the cvc target in build/ and Debian's
# /usr/bin/python3 with python3-numpy and python3-pil.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench_refinement}
cvc=build/app/cvc
source scripts/bench/bench_scenes.sh
make_scenes "$out" "$cvc"
yardstick=("$out/phantom512.mhd" "${yardstick_inside[@]}")
phantom=("$out/colon.nrrd" "${phantom_inside[@]}")
ct=("$ct_volume" "${ct_inside[@]}")
render() {  # scene-name label options...
  local name=$1 label=$2
  shift 2
  local -n scene=$name
  "$cvc" render "${scene[@]}" --iso -500 --force --hits "$out/${name}_$label.nrrd" -o "$out/${name}_$label.png" \
    "$@" > /dev/null
}
for name in yardstick phantom ct; do
  echo "rendering $name" >&2
  for step in 0.5 1; do
    for refine in 0 2 6 12; do render "$name" "s${step}_r$refine" --gradient central --step "$step" --refine "$refine"; done
  done
  render "$name" converged --step 0.1 --filter tricubic --refine 12
done
/usr/bin/python3 - "$out" <<'PY'
import sys
import numpy as np
from PIL import Image

out = sys.argv[1]

def hits(path):
    data = open(path, "rb").read()
    return np.frombuffer(data[data.index(b"\n\n") + 2:], dtype=np.float32).reshape(-1, 4)

def pixels(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(int)

def compare(a, b):
    ha, hb = hits(f"{out}/{a}.nrrd"), hits(f"{out}/{b}.nrrd")
    both = (ha[:, 3] > 0) & (hb[:, 3] > 0)
    d = np.linalg.norm(ha[both, :3] - hb[both, :3], axis=1)
    px = np.abs(pixels(f"{out}/{a}.png") - pixels(f"{out}/{b}.png")).max(axis=2)
    return (f"{d.mean():.4f} | {np.percentile(d, 99):.4f} | {d.max():.3f} | {np.percentile(px, 99):.0f} | "
            f"{px.max()} | {100 * (px > 2).mean():.2f} % |")

print("| scene | step (voxels) | compared | hit distance mean (mm) | p99 | max | pixel difference p99 | max | > 2 levels |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
for name in ("yardstick", "phantom", "ct"):
    for step in ("0.5", "1"):
        for refine in (0, 2, 6):
            print(f"| {name} | {step} | {refine} steps vs 12 | " + compare(f"{name}_s{step}_r{refine}", f"{name}_s{step}_r12"))
        print(f"| {name} | {step} | 12 steps vs 0.1-voxel tricubic | " + compare(f"{name}_s{step}_r12", f"{name}_converged"))
PY
