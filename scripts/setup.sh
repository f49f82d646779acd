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
  libvulkan-dev vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglm-dev libeigen3-dev libcli11-dev nlohmann-json3-dev
  libpng-dev zlib1g-dev
  libopenvdb-dev libtbb-dev libboost-iostreams-dev
  libgdcm-dev libgdcm-tools libnifti2-dev
  libgtest-dev googletest
  clang libclang-rt-14-dev
  chromium chromium-driver python3-selenium  # the review page's test in a headless browser
  libopenmpi-dev openmpi-bin                 # mpirun -np N cvc render ... (and its tests)
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module cvc and its tests
  python3-jsonschema                         # the Slicer files checked against the Markups schema
)

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# lavapipe (Mesa's CPU Vulkan driver) from bookworm-backports: Debian 12 ships Mesa 22.3, whose
# ray casting of a stereo frame is about 1.2x slower than Mesa 25's on the same binary, the same
# pixels (docs/benchmarks/mesa.md; 2x before the march skipped most empty samples). The
# backports suite is enabled the standard way: its packages keep apt's low priority (100), so only
# mesa-vulkan-drivers and what it needs come from there. Where backports cannot be had (another
# release, no network to it), the release's Mesa is installed instead and setup says so.
mesa_version() { dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true; }
codename=$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}")
if [[ "$(mesa_version)" != *bpo* ]]; then
  installed_backports=no
  if [ "$codename" = bookworm ]; then
    list=/etc/apt/sources.list.d/bookworm-backports.sources
    if ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
      echo "setup: enabling bookworm-backports ($list)"
      printf '%s\n' 'Types: deb' 'URIs: http://deb.debian.org/debian' 'Suites: bookworm-backports' \
        'Components: main' 'Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg' | $sudo tee "$list" >/dev/null
    fi
    if $sudo apt-get update -q && $sudo apt-get install -y -q --no-install-recommends \
        -t bookworm-backports mesa-vulkan-drivers; then
      installed_backports=yes
    fi
  fi
  if [ "$installed_backports" = no ]; then
    echo "setup: Mesa from bookworm-backports is not available here; using the release's Mesa (slower lavapipe)"
    dpkg-query -W -f='${Status}' mesa-vulkan-drivers 2>/dev/null | grep -q 'install ok installed' || {
      $sudo apt-get update -q
      $sudo apt-get install -y -q --no-install-recommends mesa-vulkan-drivers
    }
  fi
fi
echo "setup: lavapipe from mesa-vulkan-drivers $(mesa_version)"

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCVC_BUILD_TESTS=ON
cmake --build "$build_dir" --parallel "$jobs"
