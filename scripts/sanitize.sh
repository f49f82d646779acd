#!/usr/bin/env bash
# Usage: scripts/sanitize.sh [address|thread] [build-dir]
# Builds conformal-vc with sanitizers (CMake option CVC_SANITIZE) and runs its tests there, the
# Vulkan tests on lavapipe included (it runs in-process, so its calls into our code are checked).
#   address (default): AddressSanitizer + UndefinedBehaviorSanitizer with leak detection, over
#                      the whole CTest suite but for the long runs of code a shorter test also
#                      runs (sanitizers/release_only_tests.txt); build-asan. CI runs this every time.
#   thread:            ThreadSanitizer over the tests of the threaded parts (brick builds, the
#                      display pipeline's image workers, surface coverage's threads); build-tsan.
# Any report fails its test. The runtime options and the driver's proven leaks are in
# sanitizers/sanitizer_defaults.cpp; docs/robustness.md says how each was shown.
# Run scripts/setup.sh first on a fresh machine (it installs the compilers and libraries).
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-address}
case "$kind" in
  address) sanitizers="address;undefined"; build_dir=${2:-build-asan} ;;
  thread) sanitizers="thread"; build_dir=${2:-build-tsan} ;;
  *) echo "sanitize.sh: unknown kind '$kind' (address or thread)" >&2; exit 2 ;;
esac
jobs=$(nproc 2>/dev/null || echo 2)
# -O1 with line tables: compiles in 1.6x the release's time (-O2 -g takes 2.8x with the
# sanitizers), runs fast enough for the whole suite, and the reports name file and line.
# Assertions stay on (no NDEBUG): they are checks too.
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCVC_BUILD_TESTS=ON -DCVC_SANITIZE="$sanitizers" > /dev/null
cmake --build "$build_dir" --parallel "$jobs"
cd "$build_dir"
if [ "$kind" = address ]; then
  ctest --output-on-failure --parallel "$jobs" --timeout 1800 -E "$(grep -v "^#" ../sanitizers/release_only_tests.txt | paste -sd"|")"
else
  ctest --output-on-failure --parallel "$jobs" --timeout 1800 -R "$(grep -v "^#" ../sanitizers/threaded_tests.txt | paste -sd"|")"
fi
