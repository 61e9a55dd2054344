#!/usr/bin/env bash
# Builds the Python package `dirac-integrators` (imported as `dirac`; the crate dirac-py, PyO3)
# and installs it into the virtual environment at target/py (made by scripts/setup-python.sh)
# the way README.md tells a user to (`pip install -v ./dirac-py`, maturin as pip's build
# backend), with what its tests use: NumPy, pytest and SymPy. A fresh clone gets all of it from
# this script alone; nothing is installed system-wide. The build shares the workspace's target
# directory and shows cargo's progress on stderr. Prints the interpreter to use.
#
#   scripts/build-python.sh           optimized (release): what a user installs
#   scripts/build-python.sh --debug   unoptimized (the profile `quick` of dirac-py/Cargo.toml),
#                                     built in a fraction of the time; runs are many times slower
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--debug" ]; then
    export MATURIN_PEP517_ARGS="--profile quick"
fi
python=$(scripts/setup-python.sh)
if ! "$python" -c 'import numpy, pytest, sympy' 2>/dev/null; then
    "$python" -m pip install --quiet --disable-pip-version-check 'numpy>=1.21' pytest sympy >&2
fi
CARGO_TARGET_DIR="$PWD/target" "$python" -m pip install -v --disable-pip-version-check \
    --force-reinstall --no-deps ./dirac-py >&2
echo "$python"
