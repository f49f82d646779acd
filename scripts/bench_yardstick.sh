#!/usr/bin/env bash
# Sourced by the benchmark scripts (not run on its own): the speed yardstick of
# ../shared/bench/vtk in one place. Its 512x512x451 colon phantom, its inside camera as cvc
# options, and VTK 9.1's CPU ray caster on that view.
#   yardstick_phantom DIR   makes DIR/phantom512.{mhd,raw,json} once (an absolute path: the
#                           MetaImage header names its data file, and VTK renders a file it
#                           cannot find as empty space without a word)
#   yardstick_inside        array: cvc render's options for the inside camera at 1024^2
#   vtk_yardstick_ms DIR    VTK's median milliseconds for that view, iso -500 HU, 0.5-voxel
#                           step; stops the script on a black VTK image
# Needs Debian's /usr/bin/python3 with python3-numpy, and for VTK python3-vtk9, python3-pil, xvfb.

yardstick_inside=(--position 218.1386,207.6363,108.24 --look-at 216.0219,207.1811,148.24 --up 0,1,0
                  --fov 60 --size 1024x1024)

yardstick_phantom() {
  local dir
  dir=$(cd "$1" && pwd)
  [ -f "$dir/phantom512.mhd" ] || /usr/bin/python3 ../shared/bench/vtk/make_phantom.py --out "$dir/phantom512" > /dev/null
}

vtk_yardstick_ms() {
  local dir=$1
  xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/python3 ../shared/bench/vtk/render.py \
    --volume "$dir/phantom512.mhd" --mapper cpu --mode iso --camera-json "$dir/phantom512.json" --camera inside \
    --width 1024 --height 1024 --sample-distance 0.5 --png "$dir/vtk.png" 2>/dev/null |
    /usr/bin/python3 -c 'import json, sys; print(1000 * json.loads(sys.stdin.read().strip().splitlines()[-1])["median_s"])'
  /usr/bin/python3 -c 'import sys; from PIL import Image; sys.exit(Image.open(sys.argv[1]).getextrema()[0][1] == 0)' \
    "$dir/vtk.png" || { echo "$(basename "$0"): VTK's image is black (is $dir/phantom512.raw readable?)" >&2; exit 1; }
}
