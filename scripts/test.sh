#!/usr/bin/env bash
# Usage: scripts/test.sh
# Installs what is missing, builds conformal-vc in Release with tests, and runs every test
# with CTest (Vulkan tests run on the CPU driver lavapipe when no GPU is present).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
cd build
ctest --output-on-failure --parallel 2 --timeout 600
