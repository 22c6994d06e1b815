#!/usr/bin/env bash
# Re-derives the numbers the README and docs quote from the commands written
# beside them (tests/it/doc_numbers.rs), the expensive ones too (10 million
# photons per scene: about a minute), and says which quote no longer matches
# what its command gives. The cheap ones also run with ./scripts/test.sh.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
export TRAXER_CACHE="${TRAXER_CACHE:-$PWD/target/traxer-cache}"
# The tests build tables of many coatings and energy ranges (about 6 GB): a bound
# below that would drop and rebuild them during the run.
export TRAXER_CACHE_MAX_MB="${TRAXER_CACHE_MAX_MB:-100000}"
cargo test --release -- --include-ignored doc_numbers::
