#!/usr/bin/env bash
# Installs the Debian 12 packages aamap needs, and only those missing: quick when all are present.
#   tools/install-deps.sh        everything: build, run, and the whole test suite (tools/test.sh)
#   tools/install-deps.sh run    only what building the aamap binary and running it need (tools/setup.sh)
set -euo pipefail

run_packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # Vulkan: loader, headers, Mesa lavapipe (CPU device), validation layer, shader compiler
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslc spirv-tools vulkan-tools
  # libraries
  libglm-dev libembree-dev libtbb-dev libopenexr-dev libtinygltf-dev libtinyobjloader-dev
  libglfw3-dev libyaml-cpp-dev libcli11-dev libfmt-dev libspdlog-dev nlohmann-json3-dev libstb-dev
  libpugixml-dev libassimp-dev zlib1g-dev libhwy-dev
  # the report's plots (the venv is made by tools/python-env.sh)
  python3 python3-venv
)
test_packages=(
  # tests and benchmarks (xvfb + xauth: a virtual display for the viewer test, xvfb-run)
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth
  # the report page test (ctest -L browser): report.html in headless Chromium
  chromium
  # sanitizer build and libFuzzer targets (the asan preset): clang and its runtime libraries
  clang libclang-rt-14-dev
)
case "${1:-all}" in
  run) packages=("${run_packages[@]}") ;;
  all) packages=("${run_packages[@]}" "${test_packages[@]}") ;;
  *) echo "install-deps: error: unknown set '$1' (run or all)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: error: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
