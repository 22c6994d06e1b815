#!/usr/bin/env bash
# Runs the whole test suite (in release mode: the physics tests trace many
# photons), after installing what is missing: the Rust tests, then the Python
# ones (tests/python, with astropy: scripts/test-python.sh).
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# Reflectivity tables built by the tests are kept in the build folder, not in
# the user's cache (a CAST scene's tables are about 100 MB).
export TRAXER_CACHE="${TRAXER_CACHE:-$PWD/target/traxer-cache}"
cargo test --release "$@"
./scripts/test-python.sh
