#!/usr/bin/env bash
# Regenerates traxer's built-in solar axion emission tables from the standard
# solar models and the Opacity Project tables in ../shared/solar/ (not part of
# this repository; see data/solar/README.md), for B16-AGSS09met (the default)
# and B16-GS98 (the solar-model systematic):
#   data/solar/primakoff_b16_MODEL.csv      Primakoff, g_aγ = 1e-10 GeV⁻¹
#   data/solar/abc_b16_MODEL.csv            ABC, g_ae = 1e-13
#   data/solar/abc_b16_MODEL_spectrum.csv   ABC at 1 AU per process
#   data/solar/abc_b16_agss09met_process_shares.csv   each ABC process's share
#                                                     per cell (AGSS09met only)
# Usage: scripts/solar_table.sh [SHARED_SOLAR_FOLDER]
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
shared="${1:-../shared/solar}"
op="$shared/op"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cargo build --release --quiet
for model in agss09met gs98; do
  upper=$(echo "$model" | sed 's/agss09met/AGSS09met/; s/gs98/GS98/')
  file="$shared/SolarModel_B16-$upper.dat"
  ./target/release/traxer solar-flux --model "$file" \
      --radii 0.0025:0.6975:0.005 --energies 0.1:15:0.1 --out "$out/$model/primakoff" --quiet
  ./target/release/traxer solar-flux --emission abc --model "$file" --opacities "$op" \
      --radii 0.0025:0.6975:0.005 --energies 0.1125:14.9875:0.025 --out "$out/$model/abc" --quiet
  cp "$out/$model/primakoff/emission.csv" "data/solar/primakoff_b16_$model.csv"
  cp "$out/$model/abc/emission.csv" "data/solar/abc_b16_$model.csv"
  {
    echo "# dΦ/dE at 1 AU (cm⁻² s⁻¹ keV⁻¹) of data/solar/abc_b16_$model.csv per process, g_ae = 1e-13,"
    echo "# from the same computation (traxer solar-flux --emission abc, spectrum.csv; each value the cell average)."
    cut -d, -f1,3-6 "$out/$model/abc/spectrum.csv"
  } > "data/solar/abc_b16_${model}_spectrum.csv"
done
cp "$out/agss09met/abc/abc_process_shares.csv" data/solar/abc_b16_agss09met_process_shares.csv
echo "wrote data/solar/{primakoff,abc}_b16_{agss09met,gs98}.csv, abc_b16_{agss09met,gs98}_spectrum.csv, abc_b16_agss09met_process_shares.csv"
