#!/usr/bin/env bash
# Usage: scripts/bench/bench_mesa.sh [rounds] [output-folder]
# The same cvc binary on two lavapipes, side by side in one run: the Mesa that scripts/setup.sh
# installed (bookworm-backports) and Debian 12's release Mesa, unpacked beside it with dpkg -x
# (nothing is installed) and chosen with VK_DRIVER_FILES. Rounds alternate the drivers; prints
# medians per driver: the yardstick's 1024^2 inside view (../shared/bench/vtk, iso -500 HU,
# 0.5-voxel step) and one stereo Immersive Cabin frame of the colon phantom, plus whether both
# drivers wrote the same pixels. Needs python3-numpy for the yardstick phantom. Default: 3 rounds.
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-3}
out=${2:-out/bench_mesa}
cvc=build/app/cvc
mkdir -p "$out"
out=$(cd "$out" && pwd)

# The release Mesa, unpacked (apt-get download needs no root and changes nothing installed).
release=$(apt-cache madison mesa-vulkan-drivers | awk -F'|' '$2 !~ /bpo/ {gsub(/ /, "", $2); print $2; exit}')
unpacked="$out/mesa-$release"
if [ ! -f "$unpacked/lvp_icd.json" ]; then
  (cd "$out" && apt-get download "mesa-vulkan-drivers=$release" >/dev/null 2>&1)
  dpkg -x "$out"/mesa-vulkan-drivers_"${release//:/%3a}"_*.deb "$unpacked"
  printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' \
    "$unpacked/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so" > "$unpacked/lvp_icd.json"
fi
installed_icd=$(ls /usr/share/vulkan/icd.d/lvp_icd*.json | head -1)
declare -A icd=([installed]="$installed_icd" [release]="$unpacked/lvp_icd.json")

source scripts/bench/bench_scenes.sh
make_scenes "$out" "$cvc"
inside=("${yardstick_inside[@]}" --iso -500 --step 0.5)

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
for driver in installed release; do
  echo "$driver: $(VK_DRIVER_FILES=${icd[$driver]} "$cvc" render "$out/colon.nrrd" --size 8x8 --force -o "$out/probe.png" \
    | sed -n 's/^rendered 8x8 on \(.*\): ray.*/\1/p')"
done
declare -A view frame
for ((r = 0; r < rounds; ++r)); do
  for driver in installed release; do
    export VK_DRIVER_FILES=${icd[$driver]}
    v=$("$cvc" render "$out/phantom512.mhd" "${inside[@]}" --force -o "$out/inside_$driver.png" \
        | sed -n 's/.*ray casting \([0-9.]*\) ms.*/\1/p')
    f=$("$cvc" render "$out/colon.nrrd" --display ic5 --path "$out/colon.json" --frames 1 --force \
        -o "$out/frame_$driver" 2>/dev/null | sed -n 's/.*ray casting \([0-9.]*\) ms of device.*/\1/p')
    view[$driver]+="$v "
    frame[$driver]+="$f "
    unset VK_DRIVER_FILES
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
for driver in installed release; do
  echo "$driver: inside view 1024^2 ray casting median $(echo "${view[$driver]}" | median) ms (runs: ${view[$driver]}); " \
       "stereo ic5 frame ray casting median $(echo "${frame[$driver]}" | median) ms (runs: ${frame[$driver]})"
done
# Pixels of every image both drivers wrote: the largest channel difference and how many differ.
/usr/bin/python3 - "$out" <<'PY'
import glob, os, sys
import numpy as np
from matplotlib.image import imread
out = sys.argv[1]
pairs = [("inside_installed.png", "inside_release.png")]
for path in sorted(glob.glob(os.path.join(out, "frame_installed/frame_0000/*/*.png"))):
    pairs.append((os.path.relpath(path, out), os.path.relpath(path.replace("frame_installed", "frame_release"), out)))
worst, differing, total = 0, 0, 0
for a, b in pairs:
    d = np.abs(imread(os.path.join(out, a)).astype(float) - imread(os.path.join(out, b)).astype(float)) * 255
    worst = max(worst, round(d.max()))
    differing += int((d > 0.5).sum())
    total += d.size
print(f"pixels: {len(pairs)} images; largest channel difference {worst} levels; "
      f"{differing} of {total} channel values differ ({100.0 * differing / total:.4f} %)")
PY
