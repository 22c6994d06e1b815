#!/usr/bin/env bash
# Runs the whole test suite (in release mode: the physics tests trace many
# photons), after installing what is missing: the Rust tests, then the Python
# ones (tests/python, with astropy: scripts/test-python.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo test --release "$@"
./scripts/test-python.sh
