#!/usr/bin/env bash
# Makes .venv at the repo root, pinned:
#   tools/python-env.sh plots   numpy and matplotlib: the report's plots (tools/setup.sh)
#   tools/python-env.sh [all]   and the reference FLIP implementation (flip-evaluator), used by the
#                               FLIP cross-check test (ctest -L python) and tools/flip_crosscheck.py,
#                               and Ray, used by `aamap run --executor ray` (tools/ray_executor.py,
#                               ctest -L ray) (tools/test.sh)
# Idempotent: returns at once when the set asked for is complete. Exits non-zero, saying why, when
# the venv cannot be created or pip cannot reach the package registry.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=.venv
plots=(numpy==2.4.6 matplotlib==3.11.2)
case "${1:-all}" in
  plots) packages=("${plots[@]}") ;;
  all) packages=("${plots[@]}" flip-evaluator==1.7 ray==2.60.0) ;;
  *) echo "python-env: error: unknown set '$1' (plots or all)" >&2; exit 2 ;;
esac

# Every pin of the set is installed at its version.
ready() {
    "$venv/bin/python" - "${packages[@]}" <<'PY' 2>/dev/null
import sys
from importlib.metadata import version
for pin in sys.argv[1:]:
    name, want = pin.split("==")
    assert version(name) == want, pin
PY
}

if [[ -x $venv/bin/python ]] && ready; then
    echo "python-env: $venv is ready (${packages[*]})"
    exit 0
fi

if [[ ! -x $venv/bin/python ]]; then
    if ! /usr/bin/python3 -m venv "$venv"; then
        echo "python-env: could not create $venv with /usr/bin/python3 -m venv (install python3-venv)" >&2
        exit 1
    fi
fi

echo "python-env: installing ${packages[*]} into $venv"
if ! "$venv/bin/pip" install --quiet --disable-pip-version-check "${packages[@]}"; then
    echo "python-env: pip could not install ${packages[*]} (is the package registry reachable?);" >&2
    echo "python-env: the report's plots, the FLIP cross-check test (ctest -L python) and --executor ray need them" >&2
    exit 1
fi
ready || { echo "python-env: $venv is still incomplete after pip install" >&2; exit 1; }
echo "python-env: $venv is ready (${packages[*]})"
