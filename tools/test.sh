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

# Robustness (docs/robustness.md): the parser and tracer tests again under ASan+UBSan (clang), and
# a short run of every libFuzzer target over the seeds and the hostile-input corpus. Only those
# targets are built in build/asan. AAMAP_SKIP_SANITIZERS=1 skips this part (quick local runs).
if [ "${AAMAP_SKIP_SANITIZERS:-0}" != 1 ]; then
  cmake --preset asan
  cmake --build --preset asan
  ctest --preset asan -j "$(nproc)"
  ctest --preset fuzz -j "$(nproc)"
fi
