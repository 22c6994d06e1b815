#!/usr/bin/env bash
# Submits a traxer run to Slurm: an array job with one task per shard, and the
# merge as a job that starts when every shard has finished.
#
#   cluster/slurm/submit.sh SCENE PHOTONS SHARDS OUTROOT [traxer trace options...]
#
# e.g. cluster/slurm/submit.sh scenes/cast_axion_image.toml 400000000 16 runs/cast -s 7
# Results: OUTROOT/merged (the files of one run of PHOTONS photons, bit-identical);
# the shards in OUTROOT/shard-K-of-N, logs in OUTROOT/logs. Submitting the same
# command again after a failure resumes stopped shards and skips finished ones.
# Environment: TRAXER (binary, default `traxer` on PATH), SBATCH_OPTIONS (more
# sbatch options for both jobs, e.g. "--partition=short --account=axion").
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 SCENE PHOTONS SHARDS OUTROOT [traxer trace options...]" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
scene=$(realpath "$1") photons=$2 shards=$3 root=$(realpath -m "$4")
shift 4
mkdir -p "$root/logs"
traxer=${TRAXER:-$(command -v traxer || true)}
if [ -z "$traxer" ]; then
  echo "$0: no traxer on PATH; set TRAXER=/path/to/traxer" >&2
  exit 2
fi
export TRAXER=$(realpath "$traxer") TRAXER_CLUSTER=$(dirname "$here") SCENE=$scene \
  PHOTONS=$photons SHARDS=$shards OUTROOT=$root TRAXER_OPTIONS="$*"
# shellcheck disable=SC2086  # SBATCH_OPTIONS is a list of words
array=$(sbatch --parsable ${SBATCH_OPTIONS:-} --array="1-$shards" --export=ALL \
  --output="$root/logs/shard-%a.log" "$here/traxer-shards.sbatch")
array=${array%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency="afterok:$array" --export=ALL \
  --output="$root/logs/merge.log" "$here/traxer-merge.sbatch")
merge=${merge%%;*}
echo "submitted: shards = array job $array (1-$shards), merge = job $merge -> $root/merged"
echo "$array $merge" > "$root/jobs"
