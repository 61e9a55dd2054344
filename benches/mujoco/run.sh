#!/usr/bin/env bash
# dirac against MuJoCo on the 7-DoF KUKA iiwa of examples/data/iiwa14.urdf: h = 1 ms, 10^6 steps
# from the swing under gravity of dirac-jit's example urdf_arm, no contacts, limits or damping.
# A benchmark, not part of CI.
#
# MuJoCo and numpy are installed by this script only, into their own virtual environment
# (target/bench-venv-mujoco; MUJOCO_SPEC names the pip requirement, default the version the
# figures in BENCHMARKS.md were taken with). dirac's side is the example urdf_arm (release build,
# its `--machine` lines); MuJoCo's is benches/mujoco/iiwa.py (rollouts in C, single thread: RK4,
# implicitfast, Euler). First the models are checked against each other (mass matrix and energies
# at the start, the angles after short runs at 1 and 0.5 ms); then, alternately, REPS repetitions
# (default 3) of dirac's run and MuJoCo's; the table at the end (benches/mujoco/table.py) gives
# the per-step times, the ratio dirac / RK4 per repetition and its spread, and the energy errors.
# The collected lines stay in target/bench-mujoco/results.jsonl, each side's output beside it.
#
# usage: bash benches/mujoco/run.sh [REPS] [STEPS]
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
reps=${1:-3}
steps=${2:-1000000}
venv=target/bench-venv-mujoco
out=target/bench-mujoco
spec=${MUJOCO_SPEC:-mujoco==4.0.0}

if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c 'import mujoco, numpy' 2>/dev/null; then
    "$venv/bin/pip" install --quiet "$spec" numpy
fi
py="$venv/bin/python"

cargo build --release --quiet --manifest-path dirac-io/Cargo.toml --target-dir target \
    -p dirac-jit --example urdf_arm
arm=target/release/examples/urdf_arm
mkdir -p "$out"
rm -f "$out"/dirac-*.txt "$out"/mujoco-*.txt "$out"/mujoco-*.err
results="$out/results.jsonl"
: >"$results"

# The first line of file $2 that starts with $1.
line() { grep -m1 "^$1" "$2"; }

echo "== checking the models against each other"
"$arm" --steps 1 --no-chains --machine >"$out/start.txt"
"$arm" --steps 1000 --h 0.001 --no-chains --machine >"$out/check1.txt"
"$arm" --steps 2000 --h 0.0005 --no-chains --machine >"$out/check2.txt"

for rep in $(seq 1 "$reps"); do
    load=$(uptime | sed 's/.*load average: //')
    echo "== repetition $rep of $reps (load $load): dirac, $steps steps"
    "$arm" --steps "$steps" --no-chains --machine >"$out/dirac-$rep.txt"
    grep -v '^{' "$out/dirac-$rep.txt"
    run=$(line '{"run"' "$out/dirac-$rep.txt")
    echo "{\"rep\": $rep, \"load\": \"$load\", \"dirac\": ${run#'{"run": '}" >>"$results"
    echo "== repetition $rep of $reps: MuJoCo, $steps steps per integrator"
    if [ "$rep" = 1 ]; then
        extra=(--start "$(line '{"start"' "$out/start.txt")"
            --check "$(line '{"run"' "$out/check1.txt")"
            --check "$(line '{"run"' "$out/check2.txt")")
    else
        extra=()
    fi
    # Run in $out, where MuJoCo writes its log (MUJOCO_LOG.TXT) of the instability warnings a
    # diverging integrator raises; they are left out of the output here, and the table gives the
    # step after which each run diverged.
    (cd "$out" && "$root/$py" "$root/benches/mujoco/iiwa.py" --steps "$steps" "${extra[@]}" \
        >"mujoco-$rep.txt" 2>"mujoco-$rep.err")
    grep -v -e '^WARNING: Nan' -e '^$' "$out/mujoco-$rep.err" || true
    mj=$(line 'mujoco: ' "$out/mujoco-$rep.txt")
    echo "{\"rep\": $rep, \"mujoco\": ${mj#mujoco: }}" >>"$results"
done

echo "== results ($results)"
"$py" benches/mujoco/table.py "$results"
