#!/usr/bin/env bash
# Installs CasADi (from PyPI; its wheel ships IPOPT with the MUMPS linear solver) into the same
# virtual environment at target/py that scripts/setup-python.sh uses, so the CasADi + IPOPT
# baseline of examples/dmoc/cartpole_casadi.py runs on a fresh clone from this script alone and
# nothing is installed system-wide. Prints the interpreter to use:
#     "$(scripts/setup-casadi.sh)" examples/dmoc/cartpole_casadi.py
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py
if ! "$venv/bin/python" -c 'import casadi' 2>/dev/null; then
    mkdir -p target
    # Reuse the venv if setup-python.sh already made it (python3 -m venv on an existing venv
    # keeps its packages); make it otherwise.
    [ -x "$venv/bin/python" ] || python3 -m venv "$venv" >&2
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check 'casadi>=3.6' >&2
fi
echo "$venv/bin/python"
