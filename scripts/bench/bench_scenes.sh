#!/usr/bin/env bash
# Sourced by the benchmark scripts (not run on its own): the scenes of docs/benchmarks/ in one
# place. The speed yardstick of ../shared/bench/vtk (its 512x512x451 colon phantom, its inside
# camera as cvc options, and VTK 9.1's CPU ray caster on that view), the colon phantom and the
# shared 3 mm abdominal CT with their inside cameras.
#   yardstick_phantom DIR   makes DIR/phantom512.{mhd,raw,json} once (an absolute path: the
#                           MetaImage header names its data file, and VTK renders a file it
#                           cannot find as empty space without a word)
#   yardstick_inside        array: cvc render's options for the inside camera at 1024^2
#   yardstick_camera        that camera without the image size (for cvc_bench's --size N)
#   vtk_yardstick_ms DIR    VTK's median milliseconds for that view, iso -500 HU, 0.5-voxel
#                           step; stops the script on a black VTK image
#   colon_phantom DIR CVC   makes DIR/colon.nrrd with `CVC phantom` once (its centreline and
#                           polyps in DIR/colon.json)
#   phantom_inside          array: the colon phantom's inside camera at 1024^2
#   phantom_camera          that camera without the image size
#   ct_volume, ct_inside    the 3 mm CT and its camera inside the air-filled colon at 1024^2
#   ct_camera               that camera without the image size
#   make_scenes DIR CVC     makes DIR and both phantoms in it (yardstick_phantom, colon_phantom)
# scripts/bench/bench_scenes.py reads these arrays for the Python benchmark scripts.
# Needs Debian's /usr/bin/python3 with python3-numpy, and for VTK python3-vtk9, python3-pil, xvfb.

yardstick_camera=(--position 218.1386,207.6363,108.24 --look-at 216.0219,207.1811,148.24 --up 0,1,0 --fov 60)
yardstick_inside=("${yardstick_camera[@]}" --size 1024x1024)

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

colon_phantom() {
  [ -f "$1/colon.nrrd" ] || "$2" phantom -o "$1/colon.nrrd" > /dev/null
}

phantom_camera=(--position 49.182,83.585,107.125 --look-at 51.184,78.381,115.415 --up 0,0,1 --fov 90)
phantom_inside=("${phantom_camera[@]}" --size 1024x1024)

ct_volume=../shared/data/ct/ts_example_abdomen_3mm.nrrd
ct_camera=(--position 150,240,231 --look-at 124.414,235.488,246 --up 0,0,1 --fov 90)
ct_inside=("${ct_camera[@]}" --size 1024x1024)

make_scenes() {
  mkdir -p "$1"
  yardstick_phantom "$1"
  colon_phantom "$1" "$2"
}
