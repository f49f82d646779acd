#!/usr/bin/env bash
# Usage: scripts/bench/bench_march.sh [rounds] [output-folder]
# The march loop's skipping, measured in one run with every variant alternated per round
# (medians of `rounds`, default 5; ray-casting device time as `cvc render` prints it):
#   1. the VTK yardstick (../shared/bench/vtk: 512x512x451 phantom, inside camera, 1024^2, iso
#      -500 HU, 0.5-voxel step): VTK's CPU ray caster against cvc with skipping and the tile pass
#      that starts rays past empty space, skipping without the pass, and no skipping; with the
#      B-spline normals (a still's default) and central differences, each also read from the
#      gradient volume (--gradient-volume on, a display frame's default); and with central
#      differences, 6 bisection steps instead of the default 2, and 1-voxel skipping cells;
#   2. the shared 3 mm abdominal CT inside its colon (the camera of
#      docs/benchmarks/time_against_error.md, 1024^2), at steps of 0.25, 0.5, 1 and 2 voxels,
#      without skipping, with it (the tile pass deciding per tile whether the march looks at the
#      distance map) and with the march looking in every tile: `cvc_bench skipping`, which
#      alternates the three in one process, after the rounds;
#   3. one stereo frame of the Immersive Cabin at the demo's polyp pose (colon phantom, polyp 3
#      at 50 degrees, scale 4) with the exact warp, with and without skipping along bent rays,
#      and with the chord warp;
#   4. the yardstick's view in composite mode with our colon-wall transfer function, given to
#      VTK too (scripts/bench/bench_vtk_worker.py, as bench_raycaster.py runs it: the same preset,
#      opacity per mm), and to cvc with and without skipping, and with the gradient volume;
#   5. the yardstick's view timed as VTK's is (`cvc_bench view`: the median of 5 renders after
#      the first, the eye turned 0.3 degrees about the focal point each time; `cvc render` times
#      its one, first, frame), iso and composite, with the ratio to VTK paired within each round;
# and, once, the end-to-end time of one still with and without the gradient volume (which is
# computed before the first frame), and the sampling efficiency: `cvc render --stats` on the
# yardstick against the plain-trilinear ceiling of `cvc_bench ceiling` on the same volume.
# Needs the cvc target built in build/, and for VTK python3-vtk9, python3-numpy and xvfb.
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-5}
out=${2:-out/bench_march}
cvc=build/app/cvc
source scripts/bench/bench_scenes.sh
make_scenes "$out" "$cvc"
# The yardstick as NRRD too: the VTK worker of bench_raycaster.py reads NRRD.
if [ ! -f "$out/phantom512.nrrd" ]; then
  printf 'NRRD0004\ntype: short\ndimension: 3\nsizes: 512 512 451\nspacings: 0.7 0.7 0.8\nencoding: raw\nendian: little\n\n' \
    > "$out/phantom512.nrrd"
  cat "$out/phantom512.raw" >> "$out/phantom512.nrrd"
fi
echo "device: $("$cvc" render "$out/colon.nrrd" --size 8x8 --force -o "$out/probe.png" | sed -n 's/^rendered 8x8 on \(.*\): ray.*/\1/p')"
echo "machine: $(nproc) cores, load average at the start $(cut -d' ' -f1-3 /proc/loadavg)"

# Ray-casting milliseconds of one render (pinhole) or one stereo frame (display).
cvc_ms() { "$cvc" render "$@" --force 2>/dev/null | sed -n 's/.*ray casting \([0-9.]*\) ms.*/\1/p' | tail -1; }
# The median milliseconds of cvc_bench view on the yardstick's view (VTK's timing protocol).
warm_ms() {
  build/bench/cvc_bench view "$out/phantom512.mhd" "${yardstick_camera[@]}" --size 1024 --step 0.5 "$@" 2>/dev/null |
    /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["median_ms"])'
}
yardstick() { cvc_ms "$out/phantom512.mhd" "${yardstick_inside[@]}" --step 0.5 -o "$out/yardstick.png" "$@"; }
vtk_ms() { vtk_yardstick_ms "$(cd "$out" && pwd)"; }
vtk_composite_ms() {
  cat > "$out/vtk_composite_job.json" <<JOB
{"volume": "$out/phantom512.nrrd", "threads": $(nproc),
 "camera": {"position": "218.1386,207.6363,108.24", "look_at": "216.0219,207.1811,148.24", "up": "0,1,0",
            "fov": 60, "size": "1024x1024"},
 "tasks": [{"mode": "composite", "iso": -500, "step": 0.5, "step_mm": 0.35, "runs": 3,
            "png": "$out/vtk_composite.png"}],
 "result": "$out/vtk_composite.json"}
JOB
  xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/python3 scripts/bench/bench_vtk_worker.py \
    "$out/vtk_composite_job.json" > /dev/null 2>&1
  /usr/bin/python3 -c 'import json, statistics, sys
print(statistics.median(json.load(open(sys.argv[1]))["results"][0]["times_ms"]))' "$out/vtk_composite.json"
}
cabin_ms() {
  cvc_ms "$out/colon.nrrd" --display ic5 --path "$out/colon.json" --polyp 3 --polyp-elevation 50 --scale 4 \
    -o "$out/cabin" "$@"
}

declare -A times
add() { times[$1]+="$2 "; }
for ((r = 1; r <= rounds; ++r)); do
  v=$(vtk_ms)  # an assignment, so that a black VTK image stops the script
  add vtk "$v"
  for gradient in bspline central; do
    add "yard $gradient pass" "$(yardstick --iso -500 --gradient "$gradient")"
    add "yard $gradient pass+gv" "$(yardstick --iso -500 --gradient "$gradient" --gradient-volume on)"
    add "yard $gradient nopass" "$(yardstick --iso -500 --gradient "$gradient" --no-start-pass)"
    add "yard $gradient noskip" "$(yardstick --iso -500 --gradient "$gradient" --no-skip)"
  done
  add "warm central" "$(warm_ms --gradient central)"
  add "warm central+gv" "$(warm_ms --gradient central --gradient-volume on)"
  add "warm bspline+gv" "$(warm_ms --gradient bspline --gradient-volume on)"
  add "yard central refine6" "$(yardstick --iso -500 --gradient central --refine 6)"
  add "yard central cell1" "$(yardstick --iso -500 --gradient central --skip-cell 1)"
  add "cabin exact skip" "$(cabin_ms --warp exact --skip-bent-rays)"
  add "cabin exact noskip" "$(cabin_ms --warp exact --no-skip)"
  add "cabin chord" "$(cabin_ms)"
  v=$(vtk_composite_ms)
  add "vtk composite" "$v"
  add "yard composite skip" "$(yardstick --mode composite --tf colon-wall --gradient central)"
  add "yard composite skip+gv" "$(yardstick --mode composite --tf colon-wall --gradient central --gradient-volume on)"
  add "yard composite noskip" "$(yardstick --mode composite --tf colon-wall --gradient central --no-skip)"
  add "warm composite" "$(warm_ms --mode composite --tf colon-wall --gradient central)"
  add "warm composite+gv" "$(warm_ms --mode composite --tf colon-wall --gradient central --gradient-volume on)"
  echo "round $r of $rounds done (load average $(cut -d' ' -f1 /proc/loadavg))"
done
median() { printf '%s\n' $1 | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
m() { median "${times[$1]}"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }
echo
echo "| yardstick view (1024^2, 0.5 vx) | ms (median of $rounds) | runs | / VTK |"
echo "|---|---:|---|---:|"
echo "| VTK 9.1 CPU ray caster | $(m vtk) | ${times[vtk]}| 1.00 |"
for gradient in bspline central; do
  for v in pass pass+gv nopass noskip; do
    k="yard $gradient $v"
    echo "| cvc, $gradient normals, $v | $(m "$k") | ${times[$k]}| $(ratio "$(m "$k")" "$(m vtk)") |"
  done
done
for v in refine6 cell1; do
  k="yard central $v"
  echo "| cvc, central normals, pass, $v | $(m "$k") | ${times[$k]}| $(ratio "$(m "$k")" "$(m vtk)") |"
done
echo
# The CT's variants differ by a few per cent, less than separate processes vary here: they are
# alternated within one process, the volume loaded and the pipelines built once.
build/bench/cvc_bench skipping "$ct_volume" "${ct_camera[@]}" --size 1024 --iso -500 --runs "$rounds" \
  > "$out/ct_skipping.json" 2>/dev/null
echo "| 3 mm CT, step | no skipping ms | skipping ms | no skip / skip | looks in every tile ms | no skip / every tile |"
echo "|---:|---:|---:|---:|---:|---:|"
/usr/bin/python3 -c 'import json, sys
for s in json.load(open(sys.argv[1]))["steps"]:
    ms, r = s["median_ms"], s["median_ratio_none_over"]
    row = (s["step_voxels"], ms["none"], ms["per_tile"], r["per_tile"], ms["every_tile"], r["every_tile"])
    print("| %g vx | %.0f | %.0f | %.3f | %.0f | %.3f |" % row)' "$out/ct_skipping.json"
echo
echo "| ic5 stereo frame, demo pose | ms | runs |"
echo "|---|---:|---|"
for k in "cabin exact skip" "cabin exact noskip" "cabin chord"; do echo "| $k | $(m "$k") | ${times[$k]}|"; done
echo
echo "| yardstick view, composite, colon-wall (1024^2, 0.5 vx) | ms | runs | / VTK |"
echo "|---|---:|---|---:|"
echo "| VTK 9.1 CPU ray caster | $(m "vtk composite") | ${times[vtk composite]}| 1.00 |"
for v in skip skip+gv noskip; do
  k="yard composite $v"
  echo "| cvc, central normals, $v | $(m "$k") | ${times[$k]}| $(ratio "$(m "$k")" "$(m "vtk composite")") |"
done
# The median over rounds of (cvc's time / VTK's time in the same round).
paired() {
  paste <(printf '%s\n' ${times[$1]}) <(printf '%s\n' ${times[$2]}) | awk '{print $1 / $2}' | sort -g |
    awk '{a[NR]=$1} END {printf "%.2f", (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'
}
echo
echo "| yardstick view, warm frames as VTK's (1024^2, 0.5 vx) | ms (median of $rounds) | runs | / VTK, paired per round |"
echo "|---|---:|---|---:|"
for k in "warm central" "warm central+gv" "warm bspline+gv"; do
  echo "| cvc iso, ${k#warm } | $(m "$k") | ${times[$k]}| $(paired "$k" vtk) |"
done
for k in "warm composite" "warm composite+gv"; do
  echo "| cvc ${k#warm }, colon-wall | $(m "$k") | ${times[$k]}| $(paired "$k" "vtk composite") |"
done
echo
ceiling=$(build/bench/cvc_bench ceiling "$out/phantom512.mhd" --size 1024 --steps 100 --runs 5 2>/dev/null | tail -1)
echo "ceiling: $ceiling"
for extra in "--iso -500 --gradient central" "--iso -500 --gradient central --no-skip" "--mode composite --tf colon-wall --gradient central"; do
  # shellcheck disable=SC2086
  echo "stats ($extra): $("$cvc" render "$out/phantom512.mhd" "${yardstick_inside[@]}" --step 0.5 $extra --stats \
    --force -o "$out/stats.png" 2>&1 | grep -E 'fetches per ray' | tail -1)"
done
for gv in off on; do
  start=$(date +%s.%N)
  "$cvc" render "$out/phantom512.mhd" "${yardstick_inside[@]}" --step 0.5 --gradient central --gradient-volume "$gv" \
    --force -o "$out/end_to_end.png" > /dev/null 2>&1
  echo "one still end to end, gradient volume $gv: $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}') s"
done
echo "load average at the end $(cut -d' ' -f1-3 /proc/loadavg)"
