#!/usr/bin/env bash
# Regenerates traxer's built-in solar axion emission tables from the B16-AGSS09met
# standard solar model and the Opacity Project tables in ../shared/solar/ (not
# part of this repository; see data/solar/README.md):
#   data/solar/primakoff_b16_agss09met.csv      Primakoff, g_aγ = 1e-10 GeV⁻¹
#   data/solar/abc_b16_agss09met.csv            ABC, g_ae = 1e-13
#   data/solar/abc_b16_agss09met_spectrum.csv   ABC at 1 AU per process
#   data/solar/abc_b16_agss09met_process_shares.csv   each ABC process's share per cell
# Usage: scripts/solar_table.sh [MODEL_FILE [OP_FOLDER]]
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:-../shared/solar/SolarModel_B16-AGSS09met.dat}"
op="${2:-../shared/solar/op}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cargo build --release --quiet
./target/release/traxer solar-flux --model "$model" \
    --radii 0.0025:0.6975:0.005 --energies 0.1:15:0.1 --out "$out/primakoff" --quiet
./target/release/traxer solar-flux --emission abc --model "$model" --opacities "$op" \
    --radii 0.0025:0.6975:0.005 --energies 0.1125:14.9875:0.025 --out "$out/abc" --quiet
cp "$out/primakoff/emission.csv" data/solar/primakoff_b16_agss09met.csv
cp "$out/abc/emission.csv" data/solar/abc_b16_agss09met.csv
cp "$out/abc/abc_process_shares.csv" data/solar/abc_b16_agss09met_process_shares.csv
{
  echo "# dΦ/dE at 1 AU (cm⁻² s⁻¹ keV⁻¹) of data/solar/abc_b16_agss09met.csv per process, g_ae = 1e-13,"
  echo "# from the same computation (traxer solar-flux --emission abc, spectrum.csv; each value the cell average)."
  cut -d, -f1,3-6 "$out/abc/spectrum.csv"
} > data/solar/abc_b16_agss09met_spectrum.csv
echo "wrote data/solar/primakoff_b16_agss09met.csv, abc_b16_agss09met.csv, abc_b16_agss09met_spectrum.csv, abc_b16_agss09met_process_shares.csv"
