#!/usr/bin/env bash
# dirac's Gauss–Legendre integrators against REBOUND's IAS15 on Kepler's problem (a = 1, GM = 1,
# from periapsis): the evaluations and the wall time each needs for a position error of 1e-10
# after 10 and 100 orbits at e = 0.9 and e = 0.99 (examples/high_order.rs, with
# benches/rebound/kepler.py for REBOUND's side). A benchmark, not part of CI.
#
# REBOUND is installed by this script only, into its own virtual environment
# (target/bench-venv-rebound; REBOUND_SPEC names the pip requirement, default the version the
# figures in BENCHMARKS.md were taken with). Further arguments go to the example, e.g.
# `--long 100000` for the long energy run.
#
# usage: bash benches/rebound/run.sh [example options]
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=target/bench-venv-rebound
spec=${REBOUND_SPEC:-rebound==5.2.2}
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c 'import rebound' 2>/dev/null; then
    "$venv/bin/pip" install --quiet "$spec"
fi
cargo build --release --quiet --example high_order
target/release/examples/high_order --rebound "$venv/bin/python" "$@"
