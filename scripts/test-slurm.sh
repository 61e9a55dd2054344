#!/usr/bin/env bash
# The Slurm test of dirac-io, on a real single-node cluster started by
# scripts/setup-slurm.sh: submits dirac-io/examples/slurm/ensemble.sbatch as an array of 4
# shards, cancels one shard while it runs (scancel of one array element), checks that merging
# names it as missing, resubmits that element alone, resubmits the whole array (every shard is
# then skipped), merges, and checks the merged table equals the one-process ensemble bit for bit.
# Needs root (apt-get, the daemons). Prints "N passed, M failed".
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

scripts/setup-slurm.sh
cargo build --release --manifest-path dirac-io/Cargo.toml --target-dir target --bin dsp-ensemble
bin=$root/target/release/dsp-ensemble

work=$root/target/slurm-test
rm -rf "$work"
mkdir -p "$work"
cd "$work"
members=${MEMBERS:-12000}
steps=${STEPS:-1000}
"$bin" table --members "$members" --out table.csv --failing

passed=0
failed=0
check() { # check NAME COMMAND...
    local name=$1; shift
    if "$@"; then passed=$((passed + 1)); echo "ok: $name"; else failed=$((failed + 1)); echo "FAILED: $name"; fi
}

submit() { # submit [sbatch options...] -> job id
    sbatch --parsable --chdir="$work" --output="$work/dirac-dsp-%A_%a.out" \
        --export=ALL,DSP_ENSEMBLE="$bin",TABLE="$work/table.csv",OUT="$work/shards",STEPS="$steps",SHARDS=4 \
        "$@" "$root/dirac-io/examples/slurm/ensemble.sbatch"
}

wait_job() { # wait_job ID: until none of its tasks is pending or running (at most 15 minutes)
    for _ in $(seq 1 900); do
        [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
        sleep 1
    done
    echo "job $1 still queued after 15 minutes" >&2
    squeue >&2
    return 1
}

job=$(submit)
echo "submitted array job $job (4 shards of $members members × $steps steps)"
# Shard 2 runs once a CPU is free (2 tasks at a time on 2 CPUs): wait for it, let it work, cancel it.
for _ in $(seq 1 600); do
    state=$(squeue -h -j "${job}_2" -o %T 2>/dev/null || true)
    [ "$state" = RUNNING ] && break
    sleep 0.5
done
check "shard 2 started" [ "$state" = RUNNING ]
sleep 1
check "shard 2 still running when cancelled" [ "$(squeue -h -j "${job}_2" -o %T 2>/dev/null)" = RUNNING ]
scancel "${job}_2"
wait_job "$job"
check "the cancelled shard left no shard file" [ ! -e shards/shard-00002-of-00004.parquet ]
check "the other shards completed" test -e shards/shard-00000-of-00004.parquet -a -e shards/shard-00001-of-00004.parquet -a -e shards/shard-00003-of-00004.parquet
if merge_output=$("$bin" merge --out shards --shards 4 --to merged.parquet 2>&1); then merge_status=0; else merge_status=$?; fi
echo "$merge_output"
refused() { [ "$merge_status" != 0 ] && grep -q 'shards 2 of 4 are missing' <<<"$merge_output"; }
check "merge refuses, naming the missing shard" refused

again=$(submit --array=2)
echo "resubmitted shard 2 as job $again"
wait_job "$again"
check "the resubmitted shard completed" [ -e shards/shard-00002-of-00004.parquet ]
whole=$(submit)
wait_job "$whole"
check "resubmitting the whole array skips every complete shard" \
    [ "$(cat dirac-dsp-"${whole}"_*.out | grep -c 'already complete, skipped')" = 4 ]

"$bin" merge --out shards --shards 4 --to merged.parquet
RAYON_NUM_THREADS=$(nproc) "$bin" shard --table table.csv --out one --steps "$steps" --shard 0/1
check "merged = one process, bit for bit" "$bin" compare merged.parquet one/shard-00000-of-00001.parquet
echo "slurm: $passed passed, $failed failed"
[ "$failed" = 0 ]
