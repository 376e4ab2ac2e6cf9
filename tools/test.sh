#!/usr/bin/env bash
# Second command of the README (and what .ci/run calls): install what is missing, build, run the
# whole test suite headless on lavapipe with the Vulkan validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
tools/python-env.sh
cmake --preset release
cmake --build --preset release
ctest --preset release -j "$(nproc)" "$@"
