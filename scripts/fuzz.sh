#!/usr/bin/env bash
# Usage: scripts/fuzz.sh [seconds-per-target] [build-dir]
# Builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer and UBSan) and runs each
# for the given time (default 20 s) from the seed corpus in fuzz/corpus/. Exits non-zero on
# the first crash, leak, sanitizer report or timeout; the reproducer is left in the build dir.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
build_dir=$(realpath -m "${2:-build-fuzz}")

CXX=clang++ cmake -S fuzz -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build "$build_dir" --parallel "$(nproc 2>/dev/null || echo 2)"

root=$(pwd)
for target in fuzz_nrrd fuzz_metaimage fuzz_raw_spec fuzz_centreline fuzz_polyp_truth fuzz_hit_image; do
  seeds="$root/fuzz/corpus/${target#fuzz_}"
  work="$build_dir/corpus/$target"
  mkdir -p "$work"
  echo "fuzz: $target for ${seconds}s"
  # New inputs go to the scratch corpus; the checked-in seeds are only read. A failing input
  # is saved as $build_dir/<target>-crash-*.
  "$build_dir/$target" -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=1024 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$build_dir/$target-" "$work" "$seeds" 2>&1 | tail -n 6
done
