#!/usr/bin/env bash
# Usage: scripts/test.sh
# Installs what is missing, builds conformal-vc in Release with tests, fuzzes the file-header
# parsers briefly (libFuzzer, 10 s per parser), and runs every test with CTest (Vulkan tests
# run on the CPU driver lavapipe when no GPU is present). CTest's summary is the last output.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
scripts/fuzz.sh 10 build-fuzz
cd build
ctest --output-on-failure --parallel 2 --timeout 900
