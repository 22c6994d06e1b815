#!/usr/bin/env bash
# Runs the whole test suite (in release mode: the physics tests trace many
# photons), after installing what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo test --release "$@"
