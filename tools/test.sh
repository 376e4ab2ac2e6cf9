#!/usr/bin/env bash
# Second command of the README (and what .ci/run calls): install what is missing, build, run the
# whole test suite headless on lavapipe with the Vulkan validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
# The venv's downloads overlap the build (they wait on the network, the build on the cores).
tools/python-env.sh > .venv-setup.log 2>&1 &
venv_pid=$!
cmake --preset release
cmake --build --preset release
if ! wait "$venv_pid"; then cat .venv-setup.log >&2; exit 1; fi
cat .venv-setup.log
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
