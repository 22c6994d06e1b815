#!/usr/bin/env bash
# Runs the whole test suite (in release mode: the physics tests trace many
# photons), after installing what is missing: the Rust tests, then the Python
# ones (tests/python, with astropy: scripts/test-python.sh) even when the Rust
# tests fail (the exit code is still a failure). The tests that check traxer's
# solar tables against the standard solar model and the Opacity Project data
# need ../shared/solar/ beside the repository: where it is missing they are
# reported as skipped, with how many and why, at the end (CI refuses to run
# without it). Arguments go to `cargo test` (e.g. a test name filter).
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# Reflectivity tables built by the tests are kept in the build folder, not in
# the user's cache (a CAST scene's tables are about 100 MB).
export TRAXER_CACHE="${TRAXER_CACHE:-$PWD/target/traxer-cache}"
# The tests build tables of many coatings and energy ranges (about 6 GB): a bound
# below that would drop and rebuild them during the run.
export TRAXER_CACHE_MAX_MB="${TRAXER_CACHE_MAX_MB:-100000}"
failed=()
skipped=()
cargo test --release "$@" || failed+=("Rust tests (cargo test --release)")
# The Rust tests that need ../shared/solar/ are #[ignore]d with that reason and
# named shared_solar_*: run here when the data is there.
shared_rust=$(grep -c '^fn shared_solar_' tests/it/solar.rs || true)
if [ -d ../shared/solar ]; then
  if [ $# -eq 0 ]; then
    cargo test --release -- --ignored shared_solar_ ||
      failed+=("Rust tests that need ../shared/solar/")
  fi
else
  skipped+=("$shared_rust Rust tests (tests/it/solar.rs, shared_solar_*): the built-in Primakoff and ABC tables against the full computation and the ABC spectrum against Redondo 2013 need ../shared/solar/, which is not beside the repository")
fi
python_log=$(mktemp)
trap 'rm -f "$python_log"' EXIT
./scripts/test-python.sh 2>&1 | tee "$python_log" || failed+=("Python tests (scripts/test-python.sh)")
python_skips=$(awk '/^SKIPPED \[/ { gsub(/[^0-9]/, "", $2); n += $2 } END { print n + 0 }' "$python_log")
if [ "$python_skips" -gt 0 ]; then
  skipped+=("$python_skips Python tests (listed above as SKIPPED, with their reasons)")
fi
echo
echo "== test summary =="
if [ ${#skipped[@]} -gt 0 ]; then
  for s in "${skipped[@]}"; do echo "skipped: $s"; done
else
  echo "skipped: none"
fi
if [ ${#failed[@]} -gt 0 ]; then
  for f in "${failed[@]}"; do echo "FAILED: $f"; done
  exit 1
fi
echo "passed"
