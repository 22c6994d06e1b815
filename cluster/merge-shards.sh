#!/usr/bin/env bash
# Merges the N shards that run-shard.sh wrote under OUTROOT into OUTROOT/merged.
#
#   merge-shards.sh OUTROOT N
#
# traxer refuses (exit code 2, naming the folder) shards of different runs,
# duplicates, unfinished shards, and lists the missing ones.
set -euo pipefail
root=$1 n=$2
dirs=()
for k in $(seq 1 "$n"); do dirs+=("$root/shard-$k-of-$n"); done
exec "${TRAXER:-traxer}" merge -o "$root/merged" "${dirs[@]}"
