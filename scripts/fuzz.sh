#!/usr/bin/env bash
# Usage: scripts/fuzz.sh [seconds-per-target] [build-dir] [target...]
# Builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer and UBSan) and runs each
# for the given time (default 20 s) from the seed corpus in fuzz/corpus/, as many at once as
# there are CPUs. Exits non-zero when any target finds a crash, leak, sanitizer report, timeout
# or out-of-memory; the reproducer is left in the build dir as <target>-crash-* (or -leak-,
# -timeout-, -oom-) and the target's log as <target>.log.
#
#   scripts/fuzz.sh 10 build-fuzz                       CI: 10 s a target (scripts/test.sh)
#   scripts/fuzz.sh 600                                 long mode: 10 minutes a target
#   scripts/fuzz.sh 3600 build-fuzz nifti_header dicom_series   a long hunt on chosen targets
#
# Targets are named with or without their fuzz_ prefix. New inputs collect in
# <build-dir>/corpus/<target>/ and carry over from run to run; the checked-in seeds are only read.
# Reproduce a finding with: <build-dir>/<target> <input file>
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
build_dir=$(realpath -m "${2:-build-fuzz}")
shift $(($# < 2 ? $# : 2))

all_targets=(fuzz_nrrd fuzz_metaimage fuzz_raw_spec fuzz_centreline fuzz_polyp_truth fuzz_hit_image
             fuzz_cube_map fuzz_display_json fuzz_nifti_header fuzz_dicom_series)
targets=()
for name in "$@"; do
  target=fuzz_${name#fuzz_}
  if [[ ! " ${all_targets[*]} " == *" $target "* ]]; then
    echo "fuzz: unknown target '$name' (${all_targets[*]})" >&2
    exit 2
  fi
  targets+=("$target")
done
((${#targets[@]})) || targets=("${all_targets[@]}")

jobs=$(nproc 2>/dev/null || echo 2)
CXX=clang++ cmake -S fuzz -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build "$build_dir" --parallel "$jobs" --target "${targets[@]}"

root=$(pwd)
run_target() {
  local target=$1
  local seeds="$root/fuzz/corpus/${target#fuzz_}"
  local work="$build_dir/corpus/$target"
  local log="$build_dir/$target.log"
  mkdir -p "$work"
  if "$build_dir/$target" -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=1024 -timeout=10 \
      -print_final_stats=1 -artifact_prefix="$build_dir/$target-" "$work" "$seeds" > "$log" 2>&1; then
    echo "fuzz: $target ${seconds}s: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') inputs," \
         "corpus $(find "$work" "$seeds" -type f | wc -l) files"
  else
    echo "fuzz: $target FAILED; the end of $log:"
    grep -vE '^#[0-9]+' "$log" | tail -n 40
    return 1
  fi
}

# Run up to $jobs targets at once (each is one process); remember every failure.
failed=0
pids=()
for target in "${targets[@]}"; do
  run_target "$target" &
  pids+=($!)
  if ((${#pids[@]} >= jobs)); then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
exit "$failed"
