#!/usr/bin/env bash
# CasADi baseline for the scalable systems of gen.py (the pendulum chain on a cart, the periodic Toda lattice):
# generate C for the reduced (+) residual and sparse Jacobian of eq. (4.6), compile it with gcc -O3 (timed,
# under a timeout), time residual+Jacobian evaluations (median of batches). Prints one machine-readable line:
#   casadi-c: system=S n=N cse=0|1 nz=... instructions=... nnz=... gen_s=... gcc_s=... ns=...
# (gcc_s=timeout ns=NA when gcc exceeds the timeout). Progress goes to stderr.
# The generated C and the binary go to a temporary directory removed on exit, or to $CASADI_BENCH_DIR when set
# (kept, as in benches/casadi.sh).
# usage: bash benches/casadi_scaling/run.sh --system chain|lattice --n N [--cse] [--no-check]
#                                           [--gcc-timeout SECONDS (default 900)] [--batches B (default 11)]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
gen_args=() system= n= cse=0 gcc_timeout=900 batches=11
while [ $# -gt 0 ]; do
    case $1 in
        --system) system=$2; gen_args+=(--system "$2"); shift 2 ;;
        --n) n=$2; gen_args+=(--n "$2"); shift 2 ;;
        --cse) cse=1; gen_args+=(--cse); shift ;;
        --no-check) gen_args+=(--no-check); shift ;;
        --gcc-timeout) gcc_timeout=$2; shift 2 ;;
        --batches) batches=$2; shift 2 ;;
        *) echo "run.sh: unknown argument $1" >&2; exit 1 ;;
    esac
done
[ -n "$system" ] && [ -n "$n" ] || { echo "run.sh: need --system and --n" >&2; exit 1; }
if [ -z "${CASADI_BENCH_DIR:-}" ]; then
    out=$(mktemp -d)
    trap 'rm -rf "$out"' EXIT
else
    out=$CASADI_BENCH_DIR
    mkdir -p "$out"
fi
python3 -c "import casadi" 2>/dev/null || python3 -m pip install -q casadi
t0=$(date +%s.%N)
python3 "$here/gen.py" "${gen_args[@]}" "$out"
gen_s=$(echo "$(date +%s.%N) - $t0" | bc)
meta=$(cat "$out/meta.txt")   # instructions=... nnz=... nz=...
t0=$(date +%s.%N)
if timeout "$gcc_timeout" gcc -O3 -c -o "$out/scal_gen.o" "$out/scal_gen.c" -I"$out"; then
    gcc_s=$(printf '%.2f' "$(echo "$(date +%s.%N) - $t0" | bc)")
    gcc -O3 -o "$out/scal_bench" "$here/driver.c" "$out/scal_gen.o" -I"$out" -lm
    timing=$("$out/scal_bench" "$out/point.txt" "$batches")
    echo "driver: $timing" >&2
    ns=$(echo "$timing" | sed -n 's/^ns=\([^ ]*\).*/\1/p')
else
    rc=$?
    [ $rc -eq 124 ] || { echo "run.sh: gcc failed ($rc)" >&2; exit $rc; }
    gcc_s=timeout ns=NA
fi
printf 'casadi-c: system=%s n=%s cse=%s %s gen_s=%.2f gcc_s=%s ns=%s\n' \
    "$system" "$n" "$cse" "$meta" "$gen_s" "$gcc_s" "$ns"
