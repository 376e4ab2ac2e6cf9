#!/usr/bin/env bash
# Makes .venv at the repo root with the reference FLIP implementation (flip-evaluator), used by
# the FLIP cross-check test (ctest -L python) and tools/flip_crosscheck.py, and Ray, used by
# `aamap run --executor ray` (tools/ray_executor.py, ctest -L ray). Idempotent: returns
# at once when the environment is already complete. Exits non-zero, saying why, when the venv
# cannot be created or pip cannot reach the package registry.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=.venv
packages=(flip-evaluator==1.7 numpy matplotlib ray==2.60.0)

ready() {
    "$venv/bin/python" - <<'PY' 2>/dev/null
from importlib.metadata import version
import flip_evaluator, numpy, matplotlib, ray  # noqa: F401
assert version("flip-evaluator") == "1.7"
assert version("ray") == "2.60.0"
PY
}

if [[ -x $venv/bin/python ]] && ready; then
    echo "python-env: $venv is ready (flip-evaluator 1.7, ray 2.60.0)"
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
    echo "python-env: the FLIP cross-check test (ctest -L python) and --executor ray need them" >&2
    exit 1
fi
ready || { echo "python-env: $venv is still incomplete after pip install" >&2; exit 1; }
echo "python-env: $venv is ready (flip-evaluator 1.7, ray 2.60.0)"
