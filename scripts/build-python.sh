#!/usr/bin/env bash
# Builds the Python package `dirac` (dirac-py, PyO3) with maturin and installs its wheel into the
# virtual environment at target/py (made by scripts/setup-python.sh), with what its tests use:
# NumPy, pytest and SymPy. A fresh clone gets all of it from this script alone; nothing is
# installed system-wide. The build shares the workspace's target directory. Prints the
# interpreter to use.
#
#   scripts/build-python.sh           optimized (release): what a user installs
#   scripts/build-python.sh --debug   unoptimized, built in a fraction of the time: what CI's
#                                     test suite needs (its runs are short)
set -euo pipefail
cd "$(dirname "$0")/.."
profile=--release
if [ "${1:-}" = "--debug" ]; then
    profile=
fi
python=$(scripts/setup-python.sh)
if ! "$python" -c 'import maturin, numpy, pytest, sympy' 2>/dev/null; then
    "$python" -m pip install --quiet --disable-pip-version-check \
        'maturin>=1.5,<2' 'numpy>=1.21' pytest sympy >&2
fi
rm -rf target/wheels
"$(dirname "$python")/maturin" build $profile --quiet -m dirac-py/Cargo.toml \
    --target-dir target -o target/wheels >&2
"$python" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps \
    target/wheels/dirac-*.whl >&2
echo "$python"
