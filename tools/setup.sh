#!/usr/bin/env bash
# First command of the README: install what is missing, build in Release, run the default
# experiment (configs/cornell.yaml, the built-in Cornell box). Outputs land in out/cornell/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
tools/python-env.sh
cmake --preset release
cmake --build --preset release
build/release/aamap run configs/cornell.yaml -o out/cornell "$@"
echo "setup: done; open out/cornell/report.html (tables, plots, images; results.json, results.csv)"
