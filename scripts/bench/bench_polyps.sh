#!/usr/bin/env bash
# Usage: scripts/bench/bench_polyps.sh [build-dir] ["seeds"] [polyps-per-seed] [output-folder] ["displays"]
# Polyp shapes over random polyps (docs/polyps.md, "Random polyps"): for each seed a colon
# phantom with random polyps (`cvc phantom --random-polyps N --seed S`: 5-15 mm, sessile,
# pedunculated and flat, on the wall and on folds), then `cvc polyp-check` on each display
# (conformal map and linear baseline, every pose, the left, centre and right eyes, full-size
# walls), and the distribution over the polyps of 6 mm and more: per targeted pose, map and eye
# the median, 95th percentile and worst errors, the linear baseline against the conformal map,
# the measured against the predicted error, and the worst case's crops
# (scripts/bench/polyp_check_distribution.py), written to OUTPUT/DISPLAY.md and OUTPUT/DISPLAY_worst.png.
# Defaults: seeds 11 12 13 14 15, 10 polyps each, out/bench_polyps, displays ic5 cave4. About a
# minute per polyp and display on lavapipe with 2 cores. A benchmark, not a test.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
seeds=${2:-"11 12 13 14 15"}
count=${3:-10}
out=${4:-out/bench_polyps}
displays=${5:-"ic5 cave4"}
cvc="$build/app/cvc"
mkdir -p "$out"
echo "machine: $(nproc) cores, load average $(cut -d" " -f1-3 /proc/loadavg)"
for seed in $seeds; do
  [ -f "$out/seed_$seed.nrrd" ] || "$cvc" phantom --random-polyps "$count" --seed "$seed" -o "$out/seed_$seed.nrrd" >/dev/null
done
for display in $displays; do
  runs=()
  for seed in $seeds; do
    run="$out/$display/seed_$seed"
    if [ ! -f "$run/polyp_check.json" ]; then
      start=$(date +%s)
      # Only the polyps the distribution counts (6 mm and more) are checked.
      polyps=$(/usr/bin/python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))
print(",".join(str(i) for i, p in enumerate(t["polyps"]) if p["diameter_mm"] >= 6))' "$out/seed_$seed.json")
      "$cvc" polyp-check "$out/seed_$seed.nrrd" --truth "$out/seed_$seed.json" --display "$display" \
        --polyps "$polyps" --maps conformal,linear --force -o "$run" 2>/dev/null | tail -n 3
      echo "$display seed $seed: $(( $(date +%s) - start )) s"
    fi
    runs+=("$run")
  done
  /usr/bin/python3 scripts/bench/polyp_check_distribution.py "$display" "$out/$display.md" "$out/${display}_worst.png" "${runs[@]}"
done
