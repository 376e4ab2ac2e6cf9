#!/usr/bin/env bash
# First command of the README: install what is missing, build the aamap binary in Release, run the
# default experiment (configs/cornell.yaml, the built-in Cornell box). Outputs land in out/cornell/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh run
tools/python-env.sh plots
# Only the binary the experiment runs: tools/test.sh configures and builds the tests and benchmarks
# (and installs what they need). A build folder configured before keeps its settings.
if [ -f build/release/CMakeCache.txt ]; then
  cmake --preset release -DAAMAP_BUILD_TESTS="$(sed -n 's/^AAMAP_BUILD_TESTS:BOOL=//p' build/release/CMakeCache.txt)" \
    -DAAMAP_BUILD_BENCH="$(sed -n 's/^AAMAP_BUILD_BENCH:BOOL=//p' build/release/CMakeCache.txt)"
else
  cmake --preset release -DAAMAP_BUILD_TESTS=OFF -DAAMAP_BUILD_BENCH=OFF
fi
cmake --build --preset release --target aamap
build/release/aamap run configs/cornell.yaml -o out/cornell "$@"
echo "setup: done; open out/cornell/report.html (tables, plots, images; results.json, results.csv)"
