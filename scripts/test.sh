#!/usr/bin/env bash
# Usage: scripts/test.sh
# Installs what is missing, builds conformal-vc in Release with tests, fuzzes every parser
# briefly (libFuzzer, 10 s a target), runs every test with CTest (Vulkan tests run on the CPU
# driver lavapipe when no GPU is present), then builds the suite again with AddressSanitizer and
# UBSan and runs all of it there (scripts/sanitize.sh). Each stage ends with its time in
# seconds, after CTest's summary; docs/robustness.md has the breakdown.
set -euo pipefail
cd "$(dirname "$0")/.."
stage() {
  local name=$1
  shift
  local start=$SECONDS
  "$@"
  echo "test.sh: $name took $((SECONDS - start)) s"
}
run_release_suite() { (cd build && ctest --output-on-failure --parallel 2 --timeout 900); }
stage "setup and release build" scripts/setup.sh build
stage "fuzzing" scripts/fuzz.sh 10 build-fuzz
stage "release suite" run_release_suite
stage "sanitizer build and suite" scripts/sanitize.sh address build-asan
