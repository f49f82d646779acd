#!/usr/bin/env bash
# Usage: scripts/setup.sh [build-dir]
# Installs the Debian 12 packages that the build, the tests and the demo need (only those
# missing; through sudo when not root), then configures and builds conformal-vc in Release
# with tests. Safe to run again: with everything present it only runs the incremental build.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}

packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglm-dev libeigen3-dev libcli11-dev nlohmann-json3-dev
  libpng-dev zlib1g-dev
  libopenvdb-dev libtbb-dev libboost-iostreams-dev
  libgdcm-dev libgdcm-tools libnifti2-dev
  libgtest-dev googletest
  clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCVC_BUILD_TESTS=ON
cmake --build "$build_dir" --parallel "$jobs"
