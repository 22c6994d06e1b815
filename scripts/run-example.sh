#!/usr/bin/env bash
# The main job: installs what is missing, builds traxer, and traces the shipped
# Wolter-I telescope scene (analytic shells, imported mesh baffles) in an on-axis
# parallel beam. Writes out/wolter1/: sensor.npy, sensor.png, sensor_log.png,
# sensor.json and summary.json. Extra arguments go to `traxer trace`.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cargo build --release --quiet
./target/release/traxer trace scenes/wolter1_parallel.toml --photons 2000000 --out out/wolter1 "$@"
