#!/usr/bin/env bash
# CasADi's generated C for the double spherical pendulum's reduced (+) residual+Jacobian and a Newton
# stepper on it: the shared baseline (shared/bench/casadi_dsp), run with `--form cartesian`, the
# formula of dirac::paper::double_spherical_pendulum. Further arguments (e.g. --cse) are passed on.
# Prints the baseline's report, including "casadi-c: X ns per residual+Jacobian evaluation".
# The generated C and the binary go to a temporary directory removed on exit, or to
# $CASADI_BENCH_DIR when set (kept: examples/bench_table reruns the binary there).
# usage: benches/casadi.sh [--cse]      (CASADI_DSP_RUN overrides the path of the shared run.sh)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
run=${CASADI_DSP_RUN:-$here/../../shared/bench/casadi_dsp/run.sh}
[ -f "$run" ] || { echo "casadi.sh: $run not found (set CASADI_DSP_RUN)" >&2; exit 1; }
if [ -z "${CASADI_BENCH_DIR:-}" ]; then
    CASADI_BENCH_DIR=$(mktemp -d)
    trap 'rm -rf "$CASADI_BENCH_DIR"' EXIT
fi
export CASADI_BENCH_DIR
bash "$run" --form cartesian "$@"
