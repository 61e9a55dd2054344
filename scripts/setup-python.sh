#!/usr/bin/env bash
# Installs what the Python round-trip test of dirac-io needs (pyarrow, from PyPI) into a virtual
# environment at target/py, so a fresh clone gets it from this script alone and nothing is
# installed system-wide. Prints the interpreter to use.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py
if ! "$venv/bin/python" -c 'import pyarrow' 2>/dev/null; then
    mkdir -p target
    python3 -m venv "$venv" >&2
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check 'pyarrow>=14' >&2
fi
echo "$venv/bin/python"
