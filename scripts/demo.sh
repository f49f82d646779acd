#!/usr/bin/env bash
# Usage: scripts/demo.sh [output-folder]
# The product's default job. Installs what is missing, builds conformal-vc, makes the colon
# phantom (with polyps and its ground truth), and renders the 5-wall Immersive Cabin for both
# eyes through the conformal map, at the pose from which a polyp sits on the missing ceiling;
# also writes the before/after sheet (walls without the map beside walls with it), a picture of
# the shipped abdominal CT and a few stereo frames flown through its colon along the centreline
# that `cvc colon` finds (`--path auto`); and the surface coverage of the phantom's fly-through
# (how much of the colon wall the cabin shows, the unseen patches). Every folder has its index.html.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/demo}
scripts/setup.sh build
mkdir -p "$out"
cvc=build/app/cvc

"$cvc" phantom --force -o "$out/colon.nrrd"
"$cvc" render "$out/colon.nrrd" --display ic5 --path "$out/colon.json" --polyp 3 --polyp-elevation 50 \
  --scale 4 --before-after --force -o "$out/ic5_polyp"

# How much of the phantom's colon wall the cabin's fly-through shows, and where it misses.
"$cvc" coverage "$out/colon.nrrd" --path "$out/colon.json" --display ic5 --wall-size 350x262 --force \
  -o "$out/ic5_coverage"

ct=../shared/data/ct/ts_example_abdomen_3mm.nrrd
if [ -f "$ct" ]; then
  "$cvc" render "$ct" --iso -500 --size 1024x1024 --force -o "$out/abdomen_ct.png"
  # From the caecal end, where this scan's widest air-filled segment is.
  "$cvc" render "$ct" --display ic5 --path auto --retrograde --frames 4 --path-step 10 --force \
    -o "$out/abdomen_flythrough"
else
  echo "demo: $ct not found; skipping the real-CT picture"
fi

frame="$(cd "$out/ic5_polyp/frame_0000" && pwd)"
echo "demo: the 5-wall stereo set is in $frame/left and $frame/right (front, back, left, right, floor)"
echo "demo: review sheet (left eye, right eye, anaglyph): $frame/sheet.png"
echo "demo: look at the before/after sheet: $frame/before_after.png"
echo "demo: its review page (open it in a browser): $(cd "$out/ic5_polyp" && pwd)/index.html"
echo "demo: coverage of the phantom's colon wall, unseen patches: $(cd "$out/ic5_coverage" && pwd)/index.html"
[ -d "$out/abdomen_flythrough" ] && echo "demo: the CT fly-through's review page: $(cd "$out/abdomen_flythrough" && pwd)/index.html"
[ -d "$out/abdomen_flythrough" ] && echo "demo: the abdominal CT's colon and centreline: $out/abdomen_flythrough/colon/overview.png"
true
