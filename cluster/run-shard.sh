#!/usr/bin/env bash
# One shard of a traxer run, as a cluster job runs it: starts the shard, or
# resumes it from its checkpoint if an earlier attempt was stopped, or does
# nothing if it is finished. Safe to run again and again (requeued, evicted or
# resubmitted jobs).
#
#   run-shard.sh K N SCENE PHOTONS OUTROOT [traxer trace options...]
#
# writes OUTROOT/shard-K-of-N/. Environment: TRAXER (the binary, default
# `traxer` on PATH), TRAXER_THREADS (default: the CPUs the scheduler gave,
# else all), TRAXER_CHECKPOINT_EVERY (seconds, default 600), TRAXER_SHARD_BASE
# (0 if K counts from 0, as HTCondor's $(Process) does; default 1).
#
# A SIGTERM (the scheduler's warning before the time limit, an eviction) is
# passed on to traxer, which writes its checkpoint and exits with 130; under
# Slurm the task is then requeued, and the next attempt resumes.
set -uo pipefail
if [ $# -lt 5 ]; then
  echo "usage: $0 K N SCENE PHOTONS OUTROOT [traxer trace options...]" >&2
  exit 2
fi
k=$1 n=$2 scene=$3 photons=$4 root=$5
shift 5
if [ "${TRAXER_SHARD_BASE:-1}" = 0 ]; then k=$((k + 1)); fi
traxer=${TRAXER:-traxer}
every=${TRAXER_CHECKPOINT_EVERY:-600}
threads=${TRAXER_THREADS:-${SLURM_CPUS_PER_TASK:-${_CONDOR_NPROCS:-0}}}
dir="$root/shard-$k-of-$n"
mkdir -p "$root"

if [ -f "$dir/checkpoint.bin" ]; then
  cmd=("$traxer" trace --resume "$dir" -j "$threads" --checkpoint-every "$every" -q)
elif [ -f "$dir/run_state.bin" ]; then
  echo "shard $k/$n is finished: $dir"
  exit 0
else
  cmd=("$traxer" trace "$scene" -n "$photons" --shard "$k/$n" -o "$dir"
       -j "$threads" --checkpoint-every "$every" -q "$@")
fi
echo "shard $k/$n: ${cmd[*]}"
"${cmd[@]}" &
pid=$!
trap 'kill -TERM "$pid" 2>/dev/null' TERM INT
# `wait` returns early when a trapped signal arrives: wait until traxer is gone.
while true; do
  wait "$pid"
  rc=$?
  kill -0 "$pid" 2>/dev/null || break
done
if [ "$rc" -eq 130 ] && [ -n "${SLURM_JOB_ID:-}" ]; then
  echo "shard $k/$n stopped with a checkpoint; requeueing job $SLURM_JOB_ID"
  scontrol requeue "$SLURM_JOB_ID"
fi
exit "$rc"
