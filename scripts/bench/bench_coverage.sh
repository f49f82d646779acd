#!/usr/bin/env bash
# Usage: scripts/bench/bench_coverage.sh [build-dir] [repeats]
# What coverage costs beside a fly-through: the colon phantom's stereo ic5 fly-through
# (`cvc render --display`, both eyes, PNGs and sheets) against `cvc coverage` on the same path,
# frame spacing and wall size (the centre eye's walls rendered, every pixel's hit marked on the
# wall, one sheet per frame), alternated, median of the repeats. Prints the seconds and the
# ratio; docs/coverage.md quotes them.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
repeats=${2:-3}
cvc=$build/app/cvc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$cvc" phantom --force -o "$work/colon.nrrd" >/dev/null
# ic5 at the --compare wall size (350 pixels across the box): the same pixels in both runs.
cat >"$work/ic5_350.json" <<'JSON'
{"name": "ic5_350", "box_size_m": [2.95, 2.21, 2.95], "map": "conformal",
 "walls": [{"name": "front", "width": 350, "height": 262}, {"name": "back", "width": 350, "height": 262},
           {"name": "left", "width": 350, "height": 262}, {"name": "right", "width": 350, "height": 262},
           {"name": "floor", "width": 350, "height": 350}]}
JSON
seconds() { local start end; start=$(date +%s.%N); "$@" >/dev/null 2>&1; end=$(date +%s.%N); awk "BEGIN {print $end - $start}"; }
render=() coverage=()
for ((i = 0; i < repeats; ++i)); do
  render+=("$(seconds "$cvc" render "$work/colon.nrrd" --display "$work/ic5_350.json" --path "$work/colon.json" \
    --path-step 5 --force -o "$work/render")")
  coverage+=("$(seconds "$cvc" coverage "$work/colon.nrrd" --display "$work/ic5_350.json" --path "$work/colon.json" \
    --path-step 5 --force -o "$work/coverage")")
done
median() { printf '%s\n' "$@" | sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
r=$(median "${render[@]}")
c=$(median "${coverage[@]}")
frames=$(ls -d "$work"/render/frame_* | wc -l)
echo "frames: $frames (ic5, 350x262 walls, 5 mm apart)"
echo "stereo fly-through (cvc render --display): median ${r} s over $repeats runs"
echo "coverage (cvc coverage, same path and walls): median ${c} s"
awk "BEGIN {printf \"coverage / fly-through: %.2f\\n\", $c / $r}"
echo "the coverage run's own split (last run): $(/usr/bin/python3 -c "import json;print(json.load(open('$work/coverage/coverage.json'))['timing'])")"
