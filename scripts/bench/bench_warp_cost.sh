#!/usr/bin/env bash
# Usage: scripts/bench/bench_warp_cost.sh [build-dir] [runs]
# The warp's own cost (docs/benchmarks/warp.md): at the demo's pose (colon
# phantom, polyp 3 ahead at 50 degrees) one stereo ic5 frame's ray-casting device time through
# the conformal map, through an identity cube map of the same size and format (straight rays
# at the warp's price; reading the chord table, and fetching per ray as before the table), and
# without the warp, alternating; medians and paired ratios as JSON.
# A benchmark, not a test: CI does not run it.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
runs=${2:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/app/cvc" phantom --force -o "$work/colon.nrrd" >/dev/null
"$build/bench/cvc_bench" warp "$work/colon.nrrd" --path "$work/colon.json" --polyp 3 --polyp-elevation 50 \
  --display ic5 --runs "$runs"
