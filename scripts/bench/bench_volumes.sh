#!/usr/bin/env bash
# Usage: scripts/bench/bench_volumes.sh [build-dir]
# Builds a 512x512x451 CT (the shared abdomen resampled) in six formats in a scratch folder,
# then, each in a fresh process: load time and peak resident memory per format (checked
# against GNU time's own figure), brick min/max build time, and colon phantom build time.
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
cmake --build "$build_dir" --target volumes_bench cvc > /dev/null
bench="$build_dir/tests/volumes/volumes_bench"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$bench" make "$tmp"
for input in ct.nrrd ct_gzip.nrrd ct.mha ct.nii.gz dicom ct.vdb; do
  /usr/bin/time -f "  GNU time: max RSS %M KiB, %e s" "$bench" load "$tmp/$input"
done
"$bench" bricks "$tmp/ct.nrrd"
"$build_dir/app/cvc" phantom -o "$tmp/colon.nrrd"
