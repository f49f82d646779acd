#!/usr/bin/env bash
# Usage: scripts/bench/bench_stereo.sh [build-dir] [runs] [output.json]
# The stereo eyes' bent rays, time against error (docs/benchmarks/stereo.md, "Stereo rays"): at
# the demo's pose (colon phantom, polyp 3 ahead at 50 degrees, on the cabin's missing
# ceiling) one stereo ic5 frame at 4 and at 10 mm per CAVE metre: the map about each eye (the
# display default), and the warp of space about the map centre marched as one chord, as the
# polyline, by the exact warp and by the exact warp skipping along its bent rays, alternating
# (`cvc_bench stereo`). Prints a Markdown table: per mode the median device time, the median of
# the per-run ratios to the chord, the first frame (which fills the chord or polyline table),
# volume fetches per ray, and per eye the 99th-percentile level difference to the exact warp and
# the share of pixels more than 16 levels apart; the whole JSON goes to the output file.
# A benchmark, not a test: CI does not run it.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
runs=${2:-5}
json=${3:-out/bench_stereo.json}
mkdir -p "$(dirname "$json")"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/app/cvc" phantom --force -o "$work/colon.nrrd" >/dev/null
"$build/bench/cvc_bench" stereo "$work/colon.nrrd" --path "$work/colon.json" --polyp 3 --polyp-elevation 50 \
  --display ic5 --scale 4,10 --runs "$runs" >"$json"
/usr/bin/python3 - "$json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"device: {d['device']}; {d['display']}, map {d['map_size']}^2 per face, polyp {d['polyp']} at {d['polyp_elevation_deg']} degrees")
print("| scale | mode | median ms | ratio to chord | first frame ms | fetches per ray | left p99 / > 16 levels | right p99 / > 16 levels |")
print("|---:|---|---:|---:|---:|---:|---:|---:|")
for scale, e in sorted(d["scales"].items(), key=lambda kv: float(kv[0])):
    for mode in ["chord", "eye_centred", "polyline", "exact", "exact_skipping"]:
        a = e["against_exact"][mode]
        eyes = " | ".join(f"{a[eye]['p99_levels']} / {100 * a[eye]['share_over_16_levels']:.3f} %" for eye in ["left", "right"])
        print(f"| {float(scale):g} | {mode} | {e['median_ms'][mode]:.0f} | {e['median_ratio_to_chord'][mode]:.3f} | "
              f"{e['first_frame_ms'][mode]:.0f} | {e['fetches_per_ray'][mode]:.2f} | {eyes} |")
PY
