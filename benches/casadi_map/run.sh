#!/usr/bin/env bash
# CasADi `map` baseline for the periodic Toda lattice in user coordinates (gen.py): generate C for the (+) residual
# and sparse Jacobian (code size independent of n), compile it with gcc -O3 (timed, under a timeout), time
# residual+Jacobian evaluations (median of batches of about 0.2 s). Prints one machine-readable line:
#   casadi-map: n=N nnz=... c_bytes=... gen_s=... gcc_s=... ns=... jac=elem|mx
# (gcc_s=timeout ns=NA when gcc exceeds the timeout). Progress goes to stderr.
# The generated C and the binary go to a temporary directory removed on exit, or to $CASADI_BENCH_DIR when set
# (kept).
# usage: bash benches/casadi_map/run.sh --n N [--gcc-timeout SECONDS (default 900)] [--batches B (default 11)]
#                                       [--jac elem|mx (default elem)] [--no-check]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
gen_args=() n= jac=elem gcc_timeout=900 batches=11
while [ $# -gt 0 ]; do
    case $1 in
        --n) n=$2; gen_args+=(--n "$2"); shift 2 ;;
        --jac) jac=$2; gen_args+=(--jac "$2"); shift 2 ;;
        --no-check) gen_args+=(--no-check); shift ;;
        --gcc-timeout) gcc_timeout=$2; shift 2 ;;
        --batches) batches=$2; shift 2 ;;
        *) echo "run.sh: unknown argument $1" >&2; exit 1 ;;
    esac
done
[ -n "$n" ] || { echo "run.sh: need --n" >&2; exit 1; }
if [ -z "${CASADI_BENCH_DIR:-}" ]; then
    out=$(mktemp -d)
    trap 'rm -rf "$out"' EXIT
else
    out=$CASADI_BENCH_DIR
    mkdir -p "$out"
fi
python3 -c "import casadi" 2>/dev/null || python3 -m pip install -q casadi >&2
t0=$(date +%s.%N)
python3 "$here/gen.py" "${gen_args[@]}" "$out"
gen_s=$(echo "$(date +%s.%N) - $t0" | bc)
nnz=$(sed -n 's/.*nnz=\([0-9]*\).*/\1/p' "$out/meta.txt")
c_bytes=$(wc -c < "$out/map_gen.c")
ns=NA
t0=$(date +%s.%N)
if timeout "$gcc_timeout" gcc -O3 -c -o "$out/map_gen.o" "$out/map_gen.c" -I"$out"; then
    gcc_s=$(printf '%.2f' "$(echo "$(date +%s.%N) - $t0" | bc)")
    echo "gcc: ${gcc_s} s for $c_bytes bytes" >&2
    gcc -O3 -o "$out/map_bench" "$here/driver.c" "$out/map_gen.o" -I"$out" -lm
    timing=$("$out/map_bench" "$out/point.txt" "$batches")
    echo "driver: $timing" >&2
    ns=$(echo "$timing" | sed -n 's/^ns=\([^ ]*\).*/\1/p')
else
    rc=$?
    [ $rc -eq 124 ] || { echo "run.sh: gcc failed ($rc)" >&2; exit $rc; }
    gcc_s=timeout
fi
printf 'casadi-map: n=%s nnz=%s c_bytes=%s gen_s=%.2f gcc_s=%s ns=%s jac=%s\n' \
    "$n" "$nnz" "$c_bytes" "$gen_s" "$gcc_s" "$ns" "$jac"
