#!/usr/bin/env bash
# Regenerates the pictures in docs/img/ that the README shows.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
T=target/release/traxer
tmp=$(mktemp -d)
$T trace scenes/wolter1_parallel.toml -n 2000000 -D focus_shift=60 -D off_axis=0.05 --out "$tmp" -q
cp "$tmp/sensor_log.png" docs/img/wolter1_defocus_log.png
$T reflectivity --coating llnl_recipe_3 --energy 1.49,4.51,6.41 --angle 0:3:0.005 \
  --plot docs/img/llnl_recipe_3_reflectivity.png > /dev/null
$T focus scenes/panter_al_ka.toml -D figure_error=none --from=-1460 --to=-1580 --steps 13 --out "$tmp/focus" -q
cp "$tmp/focus/focus.png" docs/img/panter_al_ka_focus.png
rm -rf "$tmp"
# PANTER Al/Ti/Fe Kα: perfect figure vs the fitted figure errors, and all EEFs.
cargo run --release --quiet --example panter_pictures
