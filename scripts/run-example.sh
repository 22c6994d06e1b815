#!/usr/bin/env bash
# The main job: installs what is missing, builds traxer, and runs the PANTER Al Kα
# validation scene: the CAST LLNL telescope (13 Pt/C-coated conical shells, as
# built) lit by an X-ray source 130.297 m away, imaged on a 14 × 14 mm sensor at the
# measured best focus (1519 mm). Writes out/panter_al_ka/: sensor.npy (flux image),
# sensor.png / sensor_log.png, sensor_eef.png (encircled energy with the 50/80/90 %
# diameters), sensor_projections.csv, sensor.json and summary.json (HPD, 80 %, 90 %
# in mm and arcsec, provenance, statistics). Extra arguments go to `traxer trace`.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# Cargo builds into CARGO_TARGET_DIR when it is set.
bin="${CARGO_TARGET_DIR:-target}/release/traxer"
if [ ! -x "$bin" ]; then
  echo "run-example: building traxer (the first build compiles every dependency: about 6 minutes on 2 cores)" >&2
fi
cargo build --release
"$bin" trace scenes/panter_al_ka.toml --photons 4000000 --out out/panter_al_ka "$@"
