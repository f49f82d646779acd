#!/usr/bin/env bash
# Usage: scripts/demo.sh [output-folder]
# Installs what is missing, builds conformal-vc, and renders the default scenes to PNGs:
# an analytic ball phantom and the shipped abdominal CT (../shared/data), seen from the front.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/demo}
scripts/setup.sh build
mkdir -p "$out"
cvc=build/app/cvc

"$cvc" phantom --kind ball --size 128 --force -o "$out/ball_phantom.nrrd"
"$cvc" render "$out/ball_phantom.nrrd" --iso 0 --size 1024x1024 --force -o "$out/ball_phantom.png"

ct=../shared/data/ct/ts_example_abdomen_3mm.nrrd
if [ -f "$ct" ]; then
  "$cvc" render "$ct" --iso -500 --size 1024x1024 --force -o "$out/abdomen_ct.png"
else
  echo "demo: $ct not found; skipping the real-CT render"
fi
echo "demo: images are in $(cd "$out" && pwd)"
