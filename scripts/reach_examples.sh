#!/usr/bin/env bash
# The reach curves of docs/magnet.md: BabyIAXO (its field map) in vacuum with a
# mass scan and three helium settings, and CAST (a uniform 9 T) in vacuum, each
# traced with 1e6 photons and 9 energy bands of 1 keV, then `traxer reach`.
#
#   scripts/reach_examples.sh [OUT] [--docs]
#
# Writes OUT (default out/reach_examples: the runs and the reach folders);
# with --docs it also copies the two plots to docs/img/reach_babyiaxo.png and
# docs/img/reach_cast.png (what the docs show; without it the checkout stays
# clean). About five minutes on two cores.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
out=out/reach_examples docs=false
for a in "$@"; do
  case "$a" in --docs) docs=true ;; *) out=$a ;; esac
done
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$(dirname "$0")/.."
cargo build --release --quiet
T=target/release/traxer
common=(-n 1e6 -q --replace -D magnet=true -D emission=primakoff -D g_agamma=1e-10
  -D pixels=300 -D "energy_bins=[1,10,9]")
# Vacuum: from 0 to 0.1 eV.
$T trace scenes/babyiaxo_axion_image.toml "${common[@]}" \
  --masses 0,0.001,0.002,0.005,0.01,0.015,0.02,0.03,0.04,0.05,0.07,0.1 -o "$out/babyiaxo_vacuum"
# Helium at 1.8 K: m_γ = 0.3331 eV × √(p / 10 mbar); masses across each setting's
# coherence (|m_a² − m_γ²| L / 2E ≲ π). The middle one is the setting's m_γ, the
# brightest, on which reach places each run's signal region (the scene's mass is set
# to it too, for the run's main image).
runs=("$out/babyiaxo_vacuum")
for setting in 1:0.04 4:0.02 10:0.008; do
  p=${setting%:*} span=${setting#*:}
  masses=$(awk -v p="$p" -v s="$span" 'BEGIN { m = 0.3331 * sqrt(p / 10);
    for (k = -4; k <= 4; k++) printf "%s%.6f", (k > -4 ? "," : ""), m * (1 + s * k / 4) }')
  $T trace scenes/babyiaxo_axion_image.toml "${common[@]}" -D helium_mbar="$p" -D helium_k=1.8 \
    -D axion_mass_ev="$(echo "$masses" | cut -d, -f5)" --masses "$masses" -o "$out/babyiaxo_helium_${p}mbar"
  runs+=("$out/babyiaxo_helium_${p}mbar")
done
# BabyIAXO's planning figures (Armengaud et al., JCAP 06 (2019) 047): two bores,
# b = 1e-7 keV⁻¹ cm⁻² s⁻¹, 1.5 years at 50 % tracking in vacuum; 100 hours per
# helium setting. No --efficiency: the planning's detector efficiency 0.7 is the
# run's own gas conversion (and window), already in its counts.
$T reach "${runs[@]}" --fraction 0.8 --window 1,7 --background 1e-7 --bores 2 \
  --tracking-hours 6574.5,100,100,100 -o "$out/babyiaxo_reach"
$docs && cp "$out/babyiaxo_reach/reach.png" docs/img/reach_babyiaxo.png
# CAST: 9 T over 9.26 m, the LLNL telescope and its GridPix detector;
# illustrative figures: b = 1e-6 keV⁻¹ cm⁻² s⁻¹, 300 hours of tracking.
$T trace scenes/cast_axion_image.toml "${common[@]}" \
  --masses 0,0.002,0.005,0.01,0.015,0.02,0.03,0.04,0.05,0.07,0.1 -o "$out/cast_vacuum"
$T reach "$out/cast_vacuum" --fraction 0.8 --window 1,7 --background 1e-6 \
  --tracking-hours 300 -o "$out/cast_reach"
$docs && cp "$out/cast_reach/reach.png" docs/img/reach_cast.png
true
