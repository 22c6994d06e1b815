#!/usr/bin/env bash
# Regenerates traxer's built-in solar axion emission table,
# data/solar/primakoff_b16_agss09met.csv, from the B16-AGSS09met standard solar
# model in ../shared/solar/ (not part of this repository; see data/solar/README.md).
# Usage: scripts/solar_table.sh [MODEL_FILE]
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:-../shared/solar/SolarModel_B16-AGSS09met.dat}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cargo run --release --quiet -- solar-flux --model "$model" \
    --radii 0.0025:0.6975:0.005 --energies 0.1:15:0.1 --out "$out/solar" --quiet
cp "$out/solar/emission.csv" data/solar/primakoff_b16_agss09met.csv
echo "wrote data/solar/primakoff_b16_agss09met.csv"
